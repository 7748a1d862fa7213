"""Track a reference motion in physics with the balance controller (`controller.py`: joint PD,
balance through the momentum Jacobian, the tunable stance-foot compensation).

`Tracker` is the simulation loop around the stateless control law. On a private copy of the world's
model (the passive springs switched off; the PD's −k_d ω_a term as implicit joint damping; the feet
given soles, `foot_sole`; friction made harder, IMPRATIO), every ``control_every`` physics steps
it samples the reference at the current time (its COM target shifted after a flight, `landing`),
reads the feet's contacts (a contact that vanishes for a step bridged, `contact_memory`), asks
`controller.balance_torque` for the motor torques and the stance feet's artificial torques, applies
them and the active pushes (torques held in between), steps the physics and checks for a fall.

Recovery (after SAMCON, Liu et al. 2010: sampled corrections kept when the simulation survives
them). A tracked clip that falls has usually left the reference a few tenths of a second earlier
(a stance that sinks, a landing that comes early), and a slightly different balance target then
would have held it: the same tracker changed by one gain holds some falling clips and drops others
(docs/balance.md). So the loop keeps a copy of its state every MARK_S seconds, and at a fall it
rewinds to the copy REWINDS_S[0] before it and replays the stretch with the COM target moved by a
sampled offset (σ COM_SIGMA_M) and the root's orientation target turned by one (σ TILT_SIGMA_RAD
about each world axis), held until HOLD_S after the fall. Of the samples still up then with their
COM within RECOVERED_COM_M of the reference's (a body held up by the artificial torque far off the
reference's path is not being tracked), the one with the least mean COM error is kept and tracking
goes on from it; if none is, the next rewind is tried, and after the last the clip is played on to
its fall as the controller alone plays it. The played motion is an ordinary simulation of the
controller with those targets: nothing but the controller and the contacts moves the body.
`TrackerSettings.recoveries` bounds the falls searched past per clip (0, the default: the
controller alone, as push-survival figures need); `eigengait track` searches past up to
TRACK_RECOVERIES. The result reports how many were and how many simulations it took.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field

import mujoco
import numpy as np

from eigengait.control.balance.controller import (
    apply_foot_torques,
    balance_rig,
    balance_torque,
    foot_contacts,
    joint_gains,
    joint_layout,
)
from eigengait.control.balance.contact_memory import ContactMemory
from eigengait.control.balance.foot_sole import add_soles
from eigengait.control.balance.foot import FootModel, foot_model_for_robustness
from eigengait.control.balance.landing import LandingShift
from eigengait.control.balance.reference import Reference
from eigengait.control.balance.virtual import VirtualGains, mass_scaled_gains
from eigengait.control.balance.wbc import WholeBodyQP
from eigengait.errors import UserInputError
from eigengait.geometry import quat_angle, quat_exp, quat_mul
from eigengait.sim.root import require_free_root
from eigengait.inputs import check_choice
from eigengait.sim.falls import has_fallen
from eigengait.sim.stepping import step
from eigengait.sim.world import GRAVITY, World

PUSH_DURATION = 0.1  # s
# the tracker's friction twice as hard as the normal contact (MuJoCo's impratio; the world's is 1):
# the walks' simulated skate 4.4-7.3 -> 3.2-6.0 cm per stance and joint RMS down by 0.2-0.5° on
# the CMU clips and 44 Bandai Namco clips, the same ones tracked whole; at 3, three of those fell,
# at 10 the run's COM error passed 5 cm (docs/balance.md, "Friction as hard as")
IMPRATIO = 2.0
CONTROLLERS = ("momentum", "qp")  # `TrackerSettings.controller`
TRACK_RECOVERIES = 4  # falls `eigengait track` searches past by default


# Recovery (module doc): marks every MARK_S; a fall is searched past by rewinding REWINDS_S before
# it, in turn, and trying `recovery_samples` offsets of the COM and root orientation targets, held
# until HOLD_S after the fall; the sample still up then with the least mean COM error is kept.
MARK_S = 0.25  # s
REWINDS_S = (0.3, 0.6, 1.0, 1.5, 2.0)  # s
HOLD_S = 0.5  # s
RECOVERED_COM_M = 0.2  # a sample standing then with its COM further off the reference's is not kept
COM_SIGMA_M = np.array([0.03, 0.03, 0.015])  # a sample's COM target offset (m, world x y z)
TILT_SIGMA_RAD = np.radians(5.0)  # a sample's root orientation target offset, per world axis


def check_controller(name: str) -> None:
    """Refuse a tracking controller name that is not one of CONTROLLERS."""
    check_choice(name, CONTROLLERS, "tracking controller", "controller")


@dataclass(frozen=True)
class BodyPush:
    """A horizontal force (N, world axes) on a body for PUSH_DURATION seconds starting at time_s."""

    force: tuple[float, float, float]
    time_s: float
    body: str = "torso"


# Stiff tracking gains (N·m/rad) by joint-name suffix, for the built-in bipeds (legs 400–1000, as in
# the momentum-Jacobian tracking literature's 300–1000 range); k_d = damping_time × k_s.
BIPED_GAINS = {
    "torso": 800.0,
    "head": 100.0,
    "upper_arm": 150.0,
    "forearm": 60.0,
    "thigh": 1000.0,
    "shin": 600.0,
    "foot": 400.0,
}


@dataclass(frozen=True)
class TrackerSettings:
    """Joint gains: a joint whose name ends with a key of ``joint_gains`` gets that k_s (N·m/rad)
    and k_d = damping_time × k_s; any other joint k_s = stiffness_scale × m g l and k_d = 2 ζ
    √(k_s m l²), with m the mass and l the COM distance of the joint's subtree in the relax pose.
    The controller runs every ``control_every`` physics steps. ``virtual``: the virtual wrench's
    gains (None: `virtual.mass_scaled_gains` for the character's mass). Foot: radius and COM height
    (m), friction μ (the compensation's model, E30); ``soles``: the feet stand on their boxes, not
    only on their heel and toe spheres (`foot_sole`). ``controller``: ``momentum`` (the chapter's:
    joint PD, balance through the momentum Jacobian, the stance-foot compensation) or ``qp`` (the
    whole-body inverse dynamics of `wbc.py`, its artificial torque on the root; the gains above
    and the foot model's compensation are the momentum controller's and unused). Recovery (module
    doc): at most ``recoveries`` falls searched past, ``recovery_samples`` samples per rewind,
    drawn from a generator seeded with ``recovery_seed``."""

    joint_gains: dict = field(default_factory=lambda: dict(BIPED_GAINS))
    damping_time: float = 0.1
    stiffness_scale: float = 12.0
    damping_ratio: float = 1.0
    virtual: VirtualGains | None = None
    control_every: int = 1
    tolerance: float = 0.0
    foot_radius_m: float = 0.1
    foot_com_height_m: float = 0.05
    foot_friction: float = 1.0
    soles: bool = True
    controller: str = "qp"
    recoveries: int = 0
    recovery_samples: int = 8
    recovery_seed: int = 0


@dataclass
class TrackingResult:
    """Outcome of a tracking run; errors are RMS over control steps, torques mean magnitudes (N·m);
    foot skate of the simulated motion (m, mean per stance and of the worst stance) when the caller
    measured it."""

    duration_s: float
    fell: bool
    fall_time_s: float | None
    joint_rms_deg: float
    com_error_m: float
    artificial_torque: float
    artificial_torque_max: float
    robustness: float
    qpos: np.ndarray = field(repr=False)  # (T, nq) recorded at the reference frame rate
    frame_time: float = 0.0
    foot_skate_m: float | None = None
    foot_skate_max_m: float | None = None
    recoveries: int = 0
    recovery_simulations: int = 0

    def summary(self) -> dict:
        skate, worst = (
            None if value is None else round(value, 4)
            for value in (self.foot_skate_m, self.foot_skate_max_m)
        )
        return {
            "duration_s": round(self.duration_s, 4),
            "fell": self.fell,
            "fall_time_s": self.fall_time_s,
            "foot_skate_m": skate,
            "foot_skate_max_m": worst,
            "joint_rms_deg": round(self.joint_rms_deg, 3),
            "com_error_m": round(self.com_error_m, 4),
            "artificial_torque": round(self.artificial_torque, 3),
            "artificial_torque_max": round(self.artificial_torque_max, 3),
            "robustness": self.robustness,
            "recoveries": self.recoveries,
            "recovery_simulations": self.recovery_simulations,
        }


@dataclass
class _Run:
    """The tracking loop's state: the simulation, the controller's memories, the logs (joint
    errors, COM errors, artificial torques, recorded poses) with their lengths at a mark, the next
    recording time (s) and the sampled target offsets ((start s, end s, offset (6,)), `offset`)."""

    data: mujoco.MjData
    landing: LandingShift
    memory: ContactMemory
    logged: tuple
    logs: tuple
    next_record: float
    offsets: list

    def offset(self, t: float) -> np.ndarray | None:
        """The targets' offset (6,) at time t (s): COM (m), root rotation vector (rad, world);
        None while no offset is in force."""
        active = [offset for start, end, offset in self.offsets if start <= t < end]
        return np.sum(active, axis=0) if active else None


class Tracker:
    """Closed-loop tracking of a Reference on a private copy of the world's model."""

    def __init__(
        self,
        world: World,
        reference: Reference,
        robustness: float,
        settings: TrackerSettings = TrackerSettings(),
    ):
        check_controller(settings.controller)
        require_free_root(world.model, world.root_body, str(world.character.path), "balance")
        self.world, self.reference, self.settings = world, reference, settings
        self.model = model = copy.deepcopy(world.model)
        if settings.soles:
            add_soles(model, world.foot_spheres)
        model.opt.impratio = IMPRATIO
        self.data = mujoco.MjData(model)
        mujoco.mj_forward(model, self.data)
        self.mass = float(model.body_subtreemass[world.root_body])
        self.foot = foot_model_for_robustness(
            robustness,
            self.mass * GRAVITY,
            settings.foot_radius_m,
            settings.foot_com_height_m,
            settings.foot_friction,
        )
        joints = joint_layout(model, world.internal_qpos_joints)
        self._switch_springs_off()
        k_s, k_d = joint_gains(
            model,
            self.data,
            joints["ball"],
            joints["hinge"],
            settings.joint_gains,
            settings.damping_time,
            settings.stiffness_scale,
            settings.damping_ratio,
        )
        virtual = settings.virtual or mass_scaled_gains(self.mass)
        self.rig = balance_rig(world, model, k_s, k_d, self.foot, virtual, settings.tolerance)
        whole_body = settings.controller == "qp"
        # the PD's −k_d ω_a, integrated implicitly; the whole-body controller sets its own
        model.dof_damping[self.rig.joint_dofs] = 0.0 if whole_body else k_d[self.rig.joint_dofs]
        self.qp = WholeBodyQP(model, self.rig, reference, robustness) if whole_body else None

    def _switch_springs_off(self) -> None:
        """The character's passive springs (joint stiffness and spring actuators) off: the PD holds
        the pose."""
        model = self.model
        model.jnt_stiffness[:] = 0.0
        for a in range(model.nu):
            if model.actuator(a).name.startswith("spring:"):
                model.actuator_biasprm[a, :3] = 0.0

    # ------------------------------------------------------------------------------------ reference

    def _reference_at(self, t: float) -> dict[str, np.ndarray]:
        ref, rig = self.reference, self.rig
        i, j, a = ref.frame_at(t)
        qpos = (1 - a) * ref.qpos[i] + a * ref.qpos[j]
        for adr in list(rig.ball_qpos[:, 0]) + [rig.root_qpos + 3]:
            qpos[adr : adr + 4] /= np.linalg.norm(qpos[adr : adr + 4])
        blend = {
            name: (1 - a) * getattr(ref, name)[i] + a * getattr(ref, name)[j]
            for name in (
                "qvel",
                "com",
                "com_vel",
                "angular_momentum",
                "support",
                "com_acc",
                "angular_momentum_rate",
                "foot_points",
                "foot_height",
                "foot_transition",
                "foot_velocity",
            )
        }
        quats = (
            ref.body_quat[j]
            * np.where(np.sum(ref.body_quat[i] * ref.body_quat[j], axis=1) < 0, -1.0, 1.0)[:, None]
        )
        body_quat = (1 - a) * ref.body_quat[i] + a * quats
        body_quat /= np.linalg.norm(body_quat, axis=1, keepdims=True)
        return {"qpos": qpos, "body_quat": body_quat, **blend}

    # ------------------------------------------------------------------------------------- stepping

    def _touches_floor_off_feet(self) -> bool:
        model, data, floor = self.model, self.data, self.rig.floor
        for i in range(data.ncon):
            c = data.contact[i]
            if floor in (c.geom1, c.geom2):
                other = int(model.geom_bodyid[c.geom2 if c.geom1 == floor else c.geom1])
                if other not in self.rig.foot_of_body:
                    return True
        return False

    def _push_bodies(self, pushes: Sequence[BodyPush]) -> list[int]:
        """Body id of each push; a body the character does not have is a UserInputError."""
        ids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, p.body) for p in pushes]
        for push, body in zip(pushes, ids):
            if body < 0:
                raise UserInputError(
                    f"the push names body '{push.body}', which the character does not have.",
                    field="push",
                )
        return ids

    def _apply_pushes(self, pushes: Sequence[BodyPush], bodies: list[int], t: float) -> None:
        """Set the external forces (N, world) of the pushes active at time t (s); all others are
        zero."""
        self.data.xfrc_applied[:, :3] = 0.0
        for push, body in zip(pushes, bodies):
            if push.time_s <= t < push.time_s + PUSH_DURATION:
                self.data.xfrc_applied[body, :3] += push.force

    def _whole_body_step(self, target: dict, contacts: dict) -> float:
        """Apply the `qp` controller's torques for this control step; returns the magnitude of its
        artificial torque on the root (N·m)."""
        command = self.qp.command(self.data, target, contacts)
        self.data.ctrl[: self.world.nmotor] = command.torque
        self.data.qfrc_applied[self.qp.root_turn] = command.artificial
        return float(np.linalg.norm(command.artificial))

    def _mark(self, run: _Run) -> _Run:
        """A copy of the loop's state to rewind to."""
        data = mujoco.MjData(self.model)
        mujoco.mj_copyData(data, self.model, run.data)
        return _Run(
            data=data,
            landing=copy.deepcopy(run.landing),
            memory=copy.deepcopy(run.memory),
            logged=tuple(len(log) for log in run.logs),
            logs=run.logs,
            next_record=run.next_record,
            offsets=list(run.offsets),
        )

    def _rewind(self, run: _Run, mark: _Run) -> None:
        """Put the loop's state back to `mark` (its logs cut to their length then)."""
        mujoco.mj_copyData(run.data, self.model, mark.data)
        run.landing, run.memory = copy.deepcopy(mark.landing), copy.deepcopy(mark.memory)
        for log, length in zip(run.logs, mark.logged):
            del log[length:]
        run.next_record, run.offsets = mark.next_record, list(mark.offsets)

    def _advance(self, run: _Run, until: float, pushes, push_bodies) -> float | None:
        """Simulate from the run's state until time `until` (s); the time of a fall, or None."""
        model, data, ref = self.model, run.data, self.reference
        dt = model.opt.timestep * self.settings.control_every
        joint_err, com_err, torques, qpos_log = run.logs
        while data.time + 1e-9 < until - 0.5 * dt:
            t = data.time
            target = self._reference_at(t)
            mujoco.mj_forward(model, data)
            reference_com = target["com"]
            target["com"] = run.landing.shifted(reference_com)
            offset = run.offset(t)
            if offset is not None:  # a recovery's sample (module doc)
                target["com"] = target["com"] + offset[:3]
                root = slice(self.rig.root_qpos + 3, self.rig.root_qpos + 7)
                target["qpos"][root] = quat_mul(quat_exp(offset[3:]), target["qpos"][root])
            contacts = run.memory.bridged(foot_contacts(model, data, self.rig))
            if self.qp is None:
                command = balance_torque(model, data, self.rig, target, contacts)
                flight = command.airborne and not ref.foot_contact[ref.frame_at(t)[0]].any()
                run.landing.update(flight, data.subtree_com[self.world.root_body], reference_com)
                apply_foot_torques(data, self.rig, command)
                data.ctrl[: self.world.nmotor] = command.torque[self.rig.joint_dofs]
                artificial = command.artificial
            else:
                artificial = self._whole_body_step(target, contacts)
            self._apply_pushes(pushes, push_bodies, t)
            ball, hinge = self.rig.ball_qpos, self.rig.hinge_qpos
            joint_err.append(
                np.concatenate(
                    [
                        quat_angle(data.qpos[ball], target["qpos"][ball]),
                        np.abs(data.qpos[hinge] - target["qpos"][hinge]),
                    ]
                )
            )
            com_err.append(np.linalg.norm(data.subtree_com[self.world.root_body] - reference_com))
            torques.append(artificial)
            # a blow-up raises, naming time and body
            step(self.world, data, self.settings.control_every, model)
            com_z = data.subtree_com[self.world.root_body][2]
            up_z = self.world.root.up_z(data.qpos)
            if has_fallen(com_z, reference_com[2], up_z, self._touches_floor_off_feet()):
                return float(data.time)
            if data.time + 1e-9 >= run.next_record:
                qpos_log.append(data.qpos.copy())
                run.next_record += ref.frame_time
        return None

    def _recover(
        self, run: _Run, marks: list[_Run], fell_at: float, end: float, rng, pushes, bodies
    ) -> tuple[bool, int]:
        """Search for a branch that does not fall (module doc, "Recovery") from the fall at
        `fell_at` (s) of a clip ending at `end` (s). Returns (recovered, simulations run); the run
        is left on the kept sample or, when none was kept, at the earliest mark tried (the samples
        rewrote the logs from there), for the caller to replay the controller alone from it to its
        fall."""
        settings, sims = self.settings, 0
        until = min(fell_at + HOLD_S, end)
        sigma = np.concatenate([COM_SIGMA_M, np.full(3, TILT_SIGMA_RAD)])
        tried: set[int] = set()
        for rewind in REWINDS_S:
            base = next(
                (m for m in reversed(marks) if m.data.time <= fell_at - rewind + 1e-9), marks[0]
            )
            if id(base) in tried:  # a fall early in the clip: the rewinds reach the same mark
                continue
            tried.add(id(base))
            standing: list[tuple[float, tuple]] = []
            for _ in range(settings.recovery_samples):
                offset = (base.data.time, until, rng.normal(0.0, 1.0, 6) * sigma)
                self._rewind(run, base)
                run.offsets.append(offset)
                fell = self._advance(run, until, pushes, bodies)
                sims += 1
                if fell is None and run.logs[1][-1] <= RECOVERED_COM_M:
                    standing.append((float(np.mean(run.logs[1][base.logged[1] :])), offset))
            if standing:
                self._rewind(run, base)
                run.offsets.append(min(standing, key=lambda s: s[0])[1])
                self._advance(run, until, pushes, bodies)
                del marks[marks.index(base) + 1 :]
                return True, sims + 1
        self._rewind(run, base)  # the earliest tried: from it the caller replays the original
        return False, sims

    def run(
        self, duration_s: float | None = None, pushes: Sequence[BodyPush] = ()
    ) -> TrackingResult:
        """Simulate from the reference's first frame for duration_s (default: the whole reference),
        with the given pushes; a fall is searched past (module doc, "Recovery") at most
        `settings.recoveries` times."""
        model, ref, settings = self.model, self.reference, self.settings
        duration = ref.duration if duration_s is None else min(duration_s, ref.duration)
        data = self.data
        data.qpos[:] = ref.qpos[0]
        data.qvel[:] = ref.qvel[0]
        mujoco.mj_forward(model, data)
        push_bodies = self._push_bodies(pushes)
        dt = model.opt.timestep * settings.control_every
        run = _Run(
            data=data,
            landing=LandingShift(dt),
            memory=ContactMemory(),
            logged=(),
            logs=([], [], [], [ref.qpos[0].copy()]),
            next_record=ref.frame_time,
            offsets=[],
        )
        marks = [self._mark(run)]
        rng = np.random.default_rng(settings.recovery_seed)
        fell_at, recovered, sims = None, 0, 0
        while data.time + 0.5 * dt < duration:
            until = min(marks[-1].data.time + MARK_S, duration)
            fell_at = self._advance(run, until, pushes, push_bodies)
            if fell_at is None:
                marks.append(self._mark(run))
                # no rewind reaches behind the last mark before this horizon: a long clip keeps
                # a few seconds of marks
                horizon = data.time - max(REWINDS_S) - MARK_S
                while len(marks) > 1 and marks[1].data.time <= horizon:
                    marks.pop(0)
                continue
            if recovered >= settings.recoveries:
                break
            saved, used = self._recover(run, marks, fell_at, duration, rng, pushes, push_bodies)
            sims += used
            if not saved:
                fell_at = self._advance(run, duration, pushes, push_bodies)
                break
            recovered += 1
            fell_at = None
            marks.append(self._mark(run))
        joint_err, com_err, torques, qpos_log = run.logs
        joint_err = np.concatenate(joint_err) if joint_err else np.zeros(1)
        return TrackingResult(
            duration_s=float(data.time),
            fell=fell_at is not None,
            fall_time_s=fell_at,
            joint_rms_deg=float(np.degrees(np.sqrt(np.mean(joint_err**2)))),
            com_error_m=float(np.sqrt(np.mean(np.square(com_err)))),
            artificial_torque=float(np.mean(torques)) if torques else 0.0,
            artificial_torque_max=float(np.max(torques)) if torques else 0.0,
            robustness=self.foot.robustness,
            qpos=np.array(qpos_log),
            frame_time=ref.frame_time,
            recoveries=recovered,
            recovery_simulations=sims,
        )


def track(
    world: World,
    reference: Reference,
    robustness: float,
    settings: TrackerSettings = TrackerSettings(),
    duration_s: float | None = None,
    pushes: Sequence[BodyPush] = (),
) -> TrackingResult:
    """Track `reference` on `world`'s character with the given robustness in [0, 1]."""
    return Tracker(world, reference, robustness, settings).run(duration_s, pushes)


__all__ = ["BodyPush", "FootModel", "Tracker", "TrackerSettings", "TrackingResult", "track"]
