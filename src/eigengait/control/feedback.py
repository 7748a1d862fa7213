"""Balance feedback inside the pulse controller: linear feedback on the deviation from the gait's
own first cycle.

Every `FEEDBACK_DT` seconds the controller reads eight **features** of the creature (world frame, x
forward):

    s = (dx, dy, vx, vy, pitch, roll, ω_pitch, ω_roll)

dx, dy: the COM's horizontal offset from the support toe (the stance foot in a ground state, the
foot that last pushed off in an air state), divided by the standing COM height h; vx, vy: the COM
velocity divided by √(g h); pitch, roll: the root body's tilt (rad; pitch > 0 nose down, roll > 0
right side down); ω: the root's angular velocity about world y and x, divided by √(g/h). The
reference s* is what the same features read at the same phase of the **first cycle**, which is
played open loop; from the second cycle on, the torque

    τ_fb = B_state K (s − s*)

is added to the pulses and held until the next reading. Two families of output directions B
(mechanisms):

* ``hip`` (SIMBICON-style, Yin et al. 2007): the swing hip places the foot from the COM offset and
  velocity (sagittal: dx, vx → hip pitch; coronal: dy, vy → hip roll) and the stance hip holds the
  root's pitch and roll (pitch, ω_pitch → hip pitch; roll, ω_roll → hip roll). Eight gains, in N·m
  per normalized feature unit.
* ``modal``: the priority modes of the state's phase get Δψ = K (s − s*) (Ding, Liu & Yin 2015's
  event-based linear feedback, in the mode basis); K is (priority modes × 8) per phase, in N·m per
  normalized unit.

* ``event`` (Ding, Liu & Yin 2015's event-based feedback, with absolute targets): once per state,
  at its first reading, the state's pulse gets Δψ = K f on chosen modes of its phase, held for the
  pulse's duration. f is the eight features above with the target forward speed taken off vx, plus
  two of the COM's vertical motion: dz = (z − h) / h and vz / √(g h). It needs no reference cycle,
  so it acts from the first cycle on; K is (modes × 10) per phase, in N·m per normalized unit.

For symmetric gaits the second foot's states use the first foot's gains on mirrored features
(dy, vy, roll, ω_roll change sign) and mirrored torques.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import mujoco
import numpy as np

from eigengait.body_tree import body_joints
from eigengait.control.pulse import State
from eigengait.geometry import quat_pitch_roll, quat_to_mat
from eigengait.sim.world import GRAVITY, World

FEEDBACK_DT = 0.01  # s between feature readings (feedback torques are held in between)
FEATURES = ("dx", "dy", "vx", "vy", "pitch", "roll", "pitch_rate", "roll_rate")
MIRROR_SIGNS = np.array([1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0])
EVENT_FEATURES = FEATURES + ("dz", "vz")
EVENT_MIRROR_SIGNS = np.r_[MIRROR_SIGNS, 1.0, 1.0]
HIP_GAINS = (
    "swing_pitch_dx",
    "swing_pitch_vx",
    "swing_roll_dy",
    "swing_roll_vy",
    "stance_pitch_pitch",
    "stance_pitch_rate",
    "stance_roll_roll",
    "stance_roll_rate",
)


@dataclass
class EventGains:
    """The ``event`` mechanism: the target forward speed and, per phase, the modes it moves and
    their gains."""

    speed: float  # m/s, the forward COM speed vx is read against
    # phase -> (1-based modes, K m×10 in EVENT_FEATURES order, N·m per normalized unit)
    phases: dict[str, tuple[list[int], np.ndarray]] = field(default_factory=dict)


@dataclass
class FeedbackGains:
    """Gains of the enabled mechanisms (empty: open loop). Units: N·m per normalized feature
    unit."""

    hip: np.ndarray | None = None  # (8,) in HIP_GAINS order
    # phase -> (modes, K m×8)
    modal: dict[str, tuple[list[int], np.ndarray]] = field(default_factory=dict)
    event: EventGains | None = None

    @property
    def enabled(self) -> bool:
        """Whether a mechanism read against the first cycle (``hip``, ``modal``) is on."""
        return self.hip is not None or bool(self.modal)


def root_tilt(
    quat: np.ndarray, angvel_local: np.ndarray, upright: np.ndarray | None = None
) -> np.ndarray:
    """(pitch, roll, ω_pitch, ω_roll) of root quaternions (…×4, wxyz) and local angular velocities
    (…×3); pitch and roll as `sim.root.quat_pitch_roll` reads them (rad) from `upright` (the root's
    turn from its zero pose, `RootLayout.upright_quat`; default `quat`), ω about world y and x
    (rad/s)."""
    pitch, roll = quat_pitch_roll(quat if upright is None else upright)
    rotation = quat_to_mat(quat)  # world angular velocity = R ω_local; its x and y rows
    wx, wy = (sum(rotation[..., row, k] * angvel_local[..., k] for k in range(3)) for row in (0, 1))
    return np.stack([pitch, roll, wy, wx], axis=-1)


class FeatureReader:
    """Reads normalized features from rollout states and sensors (last axis: MuJoCo state
    / sensordata)."""

    def __init__(self, world: World):
        self.view, self.root = world.view, world.root
        h = world.standing_com_height
        self.scale = np.array(
            [
                h,
                h,
                np.sqrt(GRAVITY * h),
                np.sqrt(GRAVITY * h),
                1,
                1,
                np.sqrt(GRAVITY / h),
                np.sqrt(GRAVITY / h),
            ]
        )

    def _tilt(self, state: np.ndarray) -> np.ndarray:
        qpos, qvel = self.view.qpos(state), self.view.qvel(state)
        if self.root.quat_qpos is not None:
            a = self.root.quat_qpos
            # a free root's angular velocity: its qvel 3-5
            return root_tilt(qpos[..., a : a + 4], qvel[..., 3:6], self.root.upright_quat(qpos))
        return planar_tilt(self.root, qpos, qvel)

    def read(self, state: np.ndarray, sensors: np.ndarray, support: str) -> np.ndarray:
        """Features (…×8) with the COM offset taken from `support`'s toe."""
        com, toe, vel = (
            self.view.com(sensors),
            self.view.toe(sensors, support),
            self.view.com_velocity(sensors),
        )
        tilt = self._tilt(state)
        raw = np.concatenate([com[..., :2] - toe[..., :2], vel[..., :2], tilt], axis=-1)
        return raw / self.scale

    def read_event(
        self, state: np.ndarray, sensors: np.ndarray, support: str, speed: float
    ) -> np.ndarray:
        """The ``event`` mechanism's ten features (…×10): `read`'s with `speed` (m/s) taken off
        vx, then the COM's height above the standing one over h and its vertical speed over
        √(g h)."""
        h, root_gh = self.scale[0], self.scale[2]
        base = self.read(state, sensors, support)
        base[..., 2] -= speed / root_gh
        com, vel = self.view.com(sensors), self.view.com_velocity(sensors)
        vertical = np.stack([com[..., 2] / h - 1.0, vel[..., 2] / root_gh], axis=-1)
        return np.concatenate([base, vertical], axis=-1)


def planar_tilt(root, qpos: np.ndarray, qvel: np.ndarray) -> np.ndarray:
    """(pitch, 0, ω_pitch, 0) of a planar root from its hinge about y (rad, rad/s), for qpos (…, nq)
    and qvel (…, nv); zeros without one. The root's joints come first and each has one coordinate,
    so the hinge's qvel address equals its qpos address."""
    out = np.zeros(qpos.shape[:-1] + (4,))
    if root.pitch_qpos is not None:
        out[..., 0] = root.pitch_sign * qpos[..., root.pitch_qpos]
        out[..., 2] = root.pitch_sign * qvel[..., root.pitch_qpos]
    return out


def leg_root_joint(world: World, foot: str) -> str:
    """The internal joint nearest the root on the chain from the root to `foot`'s toe (the hip of a
    leg)."""
    model = world.model
    body = int(model.site(world.character.feet[foot].toe).bodyid[0])
    chain = []
    while body != world.root_body and body != 0:
        chain.append(body)
        body = int(model.body_parentid[body])
    joints = set(world.character.joints)
    for b in reversed(chain):
        for j in body_joints(model, b):
            if model.joint(j).name in joints:
                return model.joint(j).name
    raise ValueError(f"foot '{foot}' has no joint between it and the root")


def hip_motors(world: World, foot: str) -> tuple[int, int]:
    """Motor indices of the hip dofs whose axes lie closest to world y (pitch) and world x (roll) at
    rest."""
    model, data = world.model, world.new_data()
    j = model.joint(leg_root_joint(world, foot)).id
    body = model.jnt_bodyid[j]
    dof = model.jnt_dofadr[j]
    if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL:
        axes = data.xmat[body].reshape(3, 3).T  # rows: the child body's local axes in world
        dofs = dof + np.arange(3)
    else:
        axes = (data.xmat[body].reshape(3, 3) @ model.jnt_axis[j])[None]
        dofs = np.array([dof])
    motor = {int(d): i for i, d in enumerate(world.internal_qvel)}
    pitch = dofs[int(np.argmax(np.abs(axes[:, 1])))]
    roll = dofs[int(np.argmax(np.abs(axes[:, 0])))]
    return motor[int(pitch)], motor[int(roll)]


def hip_motors_by_foot(world: World, feet: list[str]) -> dict[str, tuple[int, int]]:
    """`hip_motors` of each distinct foot of a gait's foot sequence."""
    return {f: hip_motors(world, f) for f in dict.fromkeys(feet)}


def steps_per_reading(timestep: float) -> int:
    """Physics steps (of `timestep` s) between two feature readings, `FEEDBACK_DT` apart."""
    return max(1, int(round(FEEDBACK_DT / timestep)))


@dataclass
class StateRole:
    """Which feet a state reads and drives: support toe for features, swing and stance hips for
    `hip`."""

    support: str
    swing: str | None
    stance: str | None


def state_roles(states: list[State]) -> list[StateRole]:
    """Roles of each state of one cycle (air: the previous state's foot supports, its own foot
    swings)."""
    roles = []
    for i, s in enumerate(states):
        prev = states[i - 1].foot
        nxt = states[(i + 1) % len(states)].foot
        if s.phase == "air":
            roles.append(StateRole(support=prev, swing=s.foot, stance=None))
        else:
            roles.append(
                StateRole(support=s.foot, swing=nxt if nxt != s.foot else None, stance=s.foot)
            )
    return roles


def hip_torque(
    gains: np.ndarray,
    dev: np.ndarray,
    role: StateRole,
    motors: dict[str, tuple[int, int]],
    n_motor: int,
) -> np.ndarray:
    """SIMBICON-style torque (n_motor,) from a feature deviation `dev` (8,) and the state's
    roles."""
    tau = np.zeros(n_motor)
    if role.swing is not None:
        pitch, roll = motors[role.swing]
        tau[pitch] += gains[0] * dev[0] + gains[1] * dev[2]
        tau[roll] += gains[2] * dev[1] + gains[3] * dev[3]
    if role.stance is not None:
        pitch, roll = motors[role.stance]
        tau[pitch] += gains[4] * dev[4] + gains[5] * dev[6]
        tau[roll] += gains[6] * dev[5] + gains[7] * dev[7]
    return tau
