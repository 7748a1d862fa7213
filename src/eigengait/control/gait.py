"""A gait system: a character's world with gravity, its mode bases per phase and foot, and the pulse
controller.

`GaitParameters` holds one controller's values; `GaitSystem` turns them into per-step motor controls
and initial states for MuJoCo.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np

from eigengait.character.loader import Character
from eigengait.control.activations import sparse_to_dense
from eigengait.control.feedback import FeedbackGains
from eigengait.control.mirror import Mirror
from eigengait.control.pulse import State, control_sequence, schedule, state_torques
from eigengait.control.simbicon import SimbiconLayer, SimbiconSettings
from eigengait.control.swing_servo import ServoSettings, SwingServo
from eigengait.errors import UserInputError
from eigengait.modal.analysis import compute_modes, partner_foot
from eigengait.sim.world import World, WorldOptions, build_world


# s: a velocity mismatch of 1 rad/s counts as 0.1 rad in the cyclic constraint
VELOCITY_WEIGHT = 0.1


@dataclass
class GaitParameters:
    """One controller: timing (s), activations ψ (N·m) per (foot, phase) over ALL modes of that
    basis, q₀, q̇₀, the balance-feedback gains (none: open loop) and what starts a ground state
    (the clock or a touchdown)."""

    period: float
    air_ratio: float
    pulse_air: float
    pulse_ground: float
    activations: dict[tuple[str, str], np.ndarray]
    qpos0: np.ndarray
    qvel0: np.ndarray
    feedback: FeedbackGains = field(default_factory=FeedbackGains)
    # what starts a ground state: "clock" (fixed times) or "touchdown" (phase_clock.py)
    trigger: str = "clock"


def free_feet(feet: list[str], symmetric: bool) -> list[str]:
    """The feet of a gait whose activations are its own: the first only when a symmetric gait
    mirrors it onto the second, else each foot once."""
    return feet[:1] if symmetric and len(feet) > 1 else list(dict.fromkeys(feet))


@dataclass
class GaitSystem:
    character: Character
    pose: str | dict
    feet: list[str]
    symmetric: bool
    basis: str = "modal"
    torque_limit: float = 400.0
    options: WorldOptions = field(default_factory=WorldOptions)
    # the sketch or controller file that chose the feet: their errors name it
    source: str | Path | None = None
    # the swing-foot servo added to every simulation of the gait (None: pulses and feedback alone)
    swing_servo: ServoSettings | None = None
    # feet on the floor with each clocked foot in its ground state, pinned with it in its ground
    # modes (a trot's diagonal partner); none: the clocked foot's toe alone, as in the thesis
    stance_partners: dict[str, list[str]] = field(default_factory=dict)
    # SIMBICON's balance layer added to every simulation of the gait (None: pulses and feedback
    # alone)
    simbicon: SimbiconSettings | None = None

    def __post_init__(self):
        blamed = self.source or self.character.path
        for foot in self.feet:
            if foot not in self.character.feet:
                raise UserInputError(
                    f"character '{self.character.name}' has no foot '{foot}'",
                    file=blamed,
                    field="feet",
                    fix=f"use feet among: {', '.join(self.character.feet) or '(none)'}",
                )
        if not self.feet:
            raise UserInputError("a gait needs at least one foot", file=blamed, field="feet")
        self.world: World = build_world(self.character, self.pose, self.options)
        modal_world = build_world(
            self.character, self.pose, WorldOptions(gravity=False, floor=False)
        )
        self.air_modes = compute_modes(modal_world, "air")
        for foot, partners in self.stance_partners.items():
            if foot not in self.feet:
                raise UserInputError(
                    f"stance_partners names '{foot}', which is not one of the gait's feet",
                    file=blamed,
                    field="stance_partners",
                    fix=f"give partners for feet among: {', '.join(self.feet)}",
                )
            for partner in partners:
                partner_foot(self.character, foot, partner, blamed, f"stance_partners.{foot}")
        self.ground_modes = {
            f: compute_modes(modal_world, "ground", f, partners=self.stance_partners.get(f, ()))
            for f in dict.fromkeys(self.feet)
        }
        self.mirror = Mirror(self.world) if self.symmetric and len(self.feet) > 1 else None
        self.servo = None if self.swing_servo is None else SwingServo(self.world, self.swing_servo)
        self.balance_layer = (
            None if self.simbicon is None else SimbiconLayer(self.world, self.feet, self.simbicon)
        )
        if self.mirror is not None and len(self.feet) != 2:
            raise UserInputError(
                "a symmetric gait alternates exactly two feet",
                file=blamed,
                field="feet",
                fix="give two mirrored feet, or set symmetric: false",
            )
        if self.mirror is not None and self.stance_partners:
            self._check_mirrored_partners(blamed)

    def _check_mirrored_partners(self, blamed: str | Path) -> None:
        """A symmetric gait's second foot plays the first foot's torques mirrored, so its ground
        problem must be the first's mirror image: the same frequencies (the partners mirrored)."""
        first, second = (self.ground_modes[f].frequencies_hz for f in self.feet)
        if len(first) != len(second) or not np.allclose(first, second, rtol=1e-6):
            partners = [self.stance_partners.get(f, []) for f in self.feet]
            raise UserInputError(
                f"the stance partners of '{self.feet[0]}' {partners[0]} and of "
                f"'{self.feet[1]}' {partners[1]} are not mirror images, so the second foot "
                "cannot play the first foot's torques mirrored",
                file=blamed,
                field="stance_partners",
                fix="give each foot the mirror image of the other's partners, or set symmetric: "
                "false",
            )

    @property
    def active_feet(self) -> list[str]:
        """Feet whose activations are free parameters (the first only when mirrored)."""
        return free_feet(self.feet, self.mirror is not None)

    @property
    def torque_limits(self) -> np.ndarray:
        """Largest torque (N·m) of each motor: the character's motor limits, capped at
        `torque_limit`."""
        return np.minimum(self.torque_limit, self.world.motor_limits)

    def basis_matrix(self, foot: str, phase: str) -> np.ndarray:
        """Torque basis (n_internal × m) of a state: unit-norm mode columns, or the identity
        (canonical)."""
        if self.basis == "canonical":
            return np.eye(self.world.nmotor)
        return (
            self.air_modes.torque_basis if phase == "air" else self.ground_modes[foot].torque_basis
        )

    def mode_count(self, phase: str) -> int:
        return self.basis_matrix(self.feet[0], phase).shape[1]

    def dense_activations(
        self, sparse: Callable[[str, str], dict[int, float]], source: str | Path | None = None
    ) -> dict[tuple[str, str], np.ndarray]:
        """ψ (N·m) per (active foot, phase) over every mode of its basis, from
        `sparse(foot, phase)`: 1-based mode number -> ψ. A mode number the basis lacks is an error
        naming `source`."""
        out = {}
        for foot in self.active_feet:
            for phase in ("air", "ground"):
                out[(foot, phase)] = sparse_to_dense(
                    sparse(foot, phase),
                    self.mode_count(phase),
                    source,
                    f"activations.{foot}.{phase}",
                )
        return out

    def states(self, p: GaitParameters) -> list[State]:
        return schedule(self.feet, p.period, p.air_ratio, p.pulse_air, p.pulse_ground)

    def controls(self, p: GaitParameters, cycles: int = 1, span: float | None = None) -> np.ndarray:
        """Motor controls (nstep × model.nu) for whole cycles or the first `span` seconds."""
        states = self.states(p)
        bases = {(s.foot, s.phase): self.basis_matrix(s.foot, s.phase) for s in states}
        torques = state_torques(bases, p.activations, states, self.mirror, self.torque_limits)
        u = control_sequence(states, torques, self.world.model.opt.timestep, cycles, span)
        full = np.zeros((len(u), self.world.model.nu))
        full[:, : self.world.nmotor] = u
        return full

    def _initial_data(self, p: GaitParameters) -> mujoco.MjData:
        data = mujoco.MjData(self.world.model)
        data.qpos[:], data.qvel[:] = p.qpos0, p.qvel0
        mujoco.mj_forward(self.world.model, data)
        return data

    def initial_sensors(self, p: GaitParameters) -> np.ndarray:
        """The world's sensor readings (COM, COM velocity, feet) at (q₀, q̇₀)."""
        return self._initial_data(p).sensordata.copy()

    def initial_state(self, p: GaitParameters) -> np.ndarray:
        """MuJoCo full physics state vector of (q₀, q̇₀)."""
        data = self._initial_data(p)
        state = np.empty(mujoco.mj_stateSize(self.world.model, mujoco.mjtState.mjSTATE_FULLPHYSICS))
        mujoco.mj_getState(self.world.model, data, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        return state

    def initial_com(self, p: GaitParameters) -> np.ndarray:
        """World position (m) of the whole creature's centre of mass at q₀."""
        data = mujoco.MjData(self.world.model)
        data.qpos[:] = p.qpos0
        mujoco.mj_kinematics(self.world.model, data)
        mujoco.mj_comPos(self.world.model, data)
        return data.subtree_com[self.world.root_body].copy()

    def state_error(
        self, qpos_ref: np.ndarray, qvel_ref: np.ndarray, qpos: np.ndarray, qvel: np.ndarray
    ) -> np.ndarray:
        """φ = (Δq, τ_v·Δq̇) of a state against a reference state, root x excluded (2·nv − 1 values).

        Positions in m and rad; velocities weighted by τ_v = VELOCITY_WEIGHT s so both read as
        displacements.
        """
        dq = np.zeros(self.world.model.nv)
        mujoco.mj_differentiatePos(self.world.model, dq, 1.0, qpos_ref, qpos)
        forward = self.world.root.forward_qvel
        return np.concatenate(
            [np.delete(dq, [] if forward is None else forward), VELOCITY_WEIGHT * (qvel - qvel_ref)]
        )

    def half_cycle_error(self, p: GaitParameters, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
        """The thesis's constraint for symmetric gaits: the mirrored state at T/2 against
        (q₀, q̇₀)."""
        qt, vt = self.mirror.state(qpos, qvel)
        return self.state_error(p.qpos0, p.qvel0, qt, vt)
