"""Track a reference motion in physics: joint PD (E1–E2) plus balance through the momentum Jacobian (E3–E29),
with the tunable stance-foot compensation (E30–E32).

Per control step (every ``control_every`` physics steps, torques held in between):
1. reference pose, velocities, COM, momenta and support point interpolated at the current time;
2. joint PD: τ_pd = k_s e + k_d ω_d through the motors, while −k_d ω_a is the joint damping, which MuJoCo
   integrates implicitly (the character's passive springs are switched off for tracking);
3. stance feet = feet touching the floor; their normal forces weight the balance torques of each foot-rooted
   Jacobian (double support blends the two roots; flight has no balance torque);
4. virtual force/torque at the COM → τ_eq = Jᵀ w;
5. the balance torque that reaches each stance foot is partly cancelled by an external torque on that foot
   (``xfrc_applied``), the artificial torque; if the cancelled fraction is below ``tolerance`` the balance
   torques are switched off for that step.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field

import mujoco
import numpy as np

from eigengait.control.balance.foot import FootModel, compensation, foot_model_for_robustness
from eigengait.control.balance.momentum import (
    centroidal_inertia,
    centroidal_momentum_matrix,
    foot_rooted_momentum_matrix,
)
from eigengait.control.balance.pd import joint_error
from eigengait.control.balance.reference import Reference
from eigengait.geometry import quat_angle, quat_to_mat
from eigengait.control.balance.virtual import VirtualGains, virtual_force, virtual_torque
from eigengait.errors import UserInputError
from eigengait.sim.falls import has_fallen
from eigengait.sim.stepping import step
from eigengait.sim.world import FLOOR, GRAVITY, World

PUSH_DURATION = 0.1  # s


@dataclass(frozen=True)
class Push:
    """A horizontal force (N, world axes) on a body for PUSH_DURATION seconds starting at time_s."""

    force: tuple[float, float, float]
    time_s: float
    body: str = "torso"


# Stiff tracking gains (N·m/rad) by joint-name suffix, for the built-in bipeds (legs 400–1000, as in the
# momentum-Jacobian tracking literature's 300–1000 range); k_d = damping_time × k_s.
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
    """Joint gains: a joint whose name ends with a key of ``joint_gains`` gets that k_s (N·m/rad) and
    k_d = damping_time × k_s; any other joint k_s = stiffness_scale × m g l and k_d = 2 ζ √(k_s m l²), with m the
    mass and l the COM distance of the joint's subtree in the relax pose. The controller runs every
    ``control_every`` physics steps. Foot: radius and COM height (m), friction μ."""

    joint_gains: dict = field(default_factory=lambda: dict(BIPED_GAINS))
    damping_time: float = 0.1
    stiffness_scale: float = 12.0
    damping_ratio: float = 1.0
    virtual: VirtualGains = field(default_factory=VirtualGains)
    control_every: int = 1
    tolerance: float = 0.0
    foot_radius_m: float = 0.1
    foot_com_height_m: float = 0.05
    foot_friction: float = 1.0


@dataclass
class TrackingResult:
    """Outcome of a tracking run; errors are RMS over control steps, torques mean magnitudes (N·m); foot skate of
    the simulated motion (m, mean per stance) when the caller measured it."""

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

    def summary(self) -> dict:
        skate = None if self.foot_skate_m is None else round(self.foot_skate_m, 4)
        return {
            "duration_s": round(self.duration_s, 4),
            "fell": self.fell,
            "fall_time_s": self.fall_time_s,
            "foot_skate_m": skate,
            "joint_rms_deg": round(self.joint_rms_deg, 3),
            "com_error_m": round(self.com_error_m, 4),
            "artificial_torque": round(self.artificial_torque, 3),
            "artificial_torque_max": round(self.artificial_torque_max, 3),
            "robustness": self.robustness,
        }


def _subtree_mass_and_arm(model: mujoco.MjModel, data: mujoco.MjData, body: int) -> tuple[float, float]:
    ids = [b for b in range(body, model.nbody) if _is_descendant(model, b, body)]
    mass = model.body_mass[ids]
    com = (mass[:, None] * data.xipos[ids]).sum(0) / mass.sum()
    return float(mass.sum()), max(float(np.linalg.norm(com - data.xanchor[model.body_jntadr[body]])), 0.05)


def _is_descendant(model: mujoco.MjModel, body: int, ancestor: int) -> bool:
    while body > ancestor:
        body = int(model.body_parentid[body])
    return body == ancestor


class Tracker:
    """Closed-loop tracking of a Reference on a private copy of the world's model."""

    def __init__(
        self, world: World, reference: Reference, robustness: float, settings: TrackerSettings = TrackerSettings()
    ):
        self.world, self.reference, self.settings = world, reference, settings
        self.model = model = copy.deepcopy(world.model)
        self.data = mujoco.MjData(model)
        mujoco.mj_forward(model, self.data)
        self.mass = float(model.body_subtreemass[world.root_body])
        self.foot = foot_model_for_robustness(
            robustness, self.mass * GRAVITY, settings.foot_radius_m, settings.foot_com_height_m, settings.foot_friction
        )
        joints = world.internal_qpos_joints
        self.ball = [j for j in joints if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_BALL)]
        self.hinge = [j for j in joints if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE)]
        self.ball_qpos = np.array([model.jnt_qposadr[j] + np.arange(4) for j in self.ball], int).reshape(-1, 4)
        self.ball_dof = np.array([model.jnt_dofadr[j] + np.arange(3) for j in self.ball], int).reshape(-1, 3)
        self.hinge_qpos = np.array([model.jnt_qposadr[j] for j in self.hinge], int)
        self.hinge_dof = np.array([model.jnt_dofadr[j] for j in self.hinge], int)
        self.motor_of_dof = np.full(model.nv, -1)
        self.motor_of_dof[world.internal_qvel] = np.arange(world.nmotor)
        root_joint = int(model.body_jntadr[world.root_body])
        self.root_qpos = int(model.jnt_qposadr[root_joint])
        self.root_dofs = int(model.jnt_dofadr[root_joint]) + np.arange(6)
        self.joint_dofs = np.asarray(world.internal_qvel)
        self._set_gains()
        self.foot_bodies = {f: int(model.geom_bodyid[g[0]]) for f, g in world.foot_spheres.items()}
        self.foot_dofs = {
            f: [d for d in range(model.nv) if model.dof_bodyid[d] == b and d in set(self.joint_dofs)]
            for f, b in self.foot_bodies.items()
        }
        floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, FLOOR)
        self.floor = floor
        self.foot_body_set = set(self.foot_bodies.values())

    def _set_gains(self) -> None:
        """Switch off the passive springs; PD stiffness per joint, damping as implicit joint damping."""
        model, data, s = self.model, self.data, self.settings
        model.jnt_stiffness[:] = 0.0
        for a in range(model.nu):
            if model.actuator(a).name.startswith("spring:"):
                model.actuator_biasprm[a, :3] = 0.0
        self.k_s = np.zeros(model.nv)
        k_d = np.zeros(model.nv)
        for j in self.ball + self.hinge:
            n = 3 if j in self.ball else 1
            dofs = model.jnt_dofadr[j] + np.arange(n)
            name = model.joint(j).name
            named = [v for k, v in s.joint_gains.items() if name.endswith(k)]
            if named:
                self.k_s[dofs] = named[0]
                k_d[dofs] = s.damping_time * named[0]
                continue
            mass, arm = _subtree_mass_and_arm(model, data, int(model.jnt_bodyid[j]))
            kp = s.stiffness_scale * mass * GRAVITY * arm
            self.k_s[dofs] = kp
            k_d[dofs] = 2.0 * s.damping_ratio * np.sqrt(kp * mass * arm * arm)
        model.dof_damping[self.joint_dofs] = k_d[self.joint_dofs]
        self.k_d = k_d

    # ------------------------------------------------------------------------------------------ reference

    def _reference_at(self, t: float) -> dict[str, np.ndarray]:
        ref = self.reference
        i, j, a = ref.frame_at(t)
        qpos = (1 - a) * ref.qpos[i] + a * ref.qpos[j]
        for adr in list(self.ball_qpos[:, 0]) + [self.root_qpos + 3]:
            qpos[adr : adr + 4] /= np.linalg.norm(qpos[adr : adr + 4])
        blend = {
            name: (1 - a) * getattr(ref, name)[i] + a * getattr(ref, name)[j]
            for name in ("qvel", "com", "com_vel", "angular_momentum", "support", "com_acc", "angular_momentum_rate")
        }
        return {"qpos": qpos, **blend}

    # ------------------------------------------------------------------------------------------- stepping

    def _stance_forces(self) -> dict[str, float]:
        """Normal contact force (N) between the floor and each foot body."""
        model, data = self.model, self.data
        forces = {f: 0.0 for f in self.foot_bodies}
        wrench = np.zeros(6)
        body_to_foot = {b: f for f, b in self.foot_bodies.items()}
        for i in range(data.ncon):
            c = data.contact[i]
            if self.floor not in (c.geom1, c.geom2):
                continue
            other = int(model.geom_bodyid[c.geom2 if c.geom1 == self.floor else c.geom1])
            if other in body_to_foot:
                mujoco.mj_contactForce(model, data, i, wrench)
                forces[body_to_foot[other]] += wrench[0]
        return forces

    def _touches_floor_off_feet(self) -> bool:
        model, data = self.model, self.data
        for i in range(data.ncon):
            c = data.contact[i]
            if self.floor in (c.geom1, c.geom2):
                other = int(model.geom_bodyid[c.geom2 if c.geom1 == self.floor else c.geom1])
                if other not in self.foot_body_set and self.model.body_parentid[other] not in self.foot_body_set:
                    return True
        return False

    def _pd(self, ref: dict[str, np.ndarray]) -> np.ndarray:
        """Motor torques of the PD part (the −k_d ω_a term is the implicit joint damping)."""
        data, tau = self.data, np.zeros(self.model.nv)
        if len(self.ball):
            err = joint_error(data.qpos[self.ball_qpos], ref["qpos"][self.ball_qpos])
            tau[self.ball_dof] = err * self.k_s[self.ball_dof]
        if len(self.hinge):
            tau[self.hinge_dof] = (ref["qpos"][self.hinge_qpos] - data.qpos[self.hinge_qpos]) * self.k_s[self.hinge_dof]
        return tau + self.k_d * ref["qvel"]

    def _balance(self, ref: dict[str, np.ndarray], forces: dict[str, float]) -> tuple[np.ndarray, float]:
        """τ_eq (nv,) and the artificial torque magnitude (N·m) applied to the stance feet this step."""
        model, data, root = self.model, self.data, self.world.root_body
        tau = np.zeros(model.nv)
        self.data.xfrc_applied[list(self.foot_body_set), 3:] = 0.0
        stance = {f: n for f, n in forces.items() if n > 1e-6}
        if not stance:
            return tau, 0.0
        total = sum(stance.values())
        points = {f: data.geom_xpos[self.world.foot_spheres[f]][:, :2].mean(axis=0) for f in stance}
        support = np.mean(list(points.values()), axis=0)
        mujoco.mj_subtreeVel(model, data)
        com, com_vel, angmom = data.subtree_com[root], data.subtree_linvel[root], data.subtree_angmom[root]
        gains = self.settings.virtual
        force = virtual_force(
            com, com_vel, support, ref["com"], ref["com_vel"], ref["support"], self.mass, GRAVITY, gains, ref["com_acc"]
        )
        quat = data.qpos[self.root_qpos + 3 : self.root_qpos + 7]
        quat_ref = ref["qpos"][self.root_qpos + 3 : self.root_qpos + 7]
        omega = quat_to_mat(quat) @ data.qvel[self.root_dofs[3:]]
        omega_ref = quat_to_mat(quat_ref) @ ref["qvel"][self.root_dofs[3:]]
        torque = virtual_torque(
            quat, quat_ref, omega, omega_ref, angmom, ref["angular_momentum"], gains, ref["angular_momentum_rate"]
        )
        wrench = np.concatenate([torque, force])
        momentum = centroidal_momentum_matrix(model, data, root)
        inertia = centroidal_inertia(model, data, root)
        for f, normal in stance.items():
            rooted = foot_rooted_momentum_matrix(
                model, data, momentum, self.foot_bodies[f], self.root_dofs, self.joint_dofs
            )
            jac = np.linalg.solve(inertia, rooted)
            tau[self.joint_dofs] += normal / total * (jac.T @ wrench)
        artificial, ratios = {}, []
        jacr = np.zeros((3, model.nv))
        for f in stance:
            mujoco.mj_jacBody(model, data, None, jacr, self.foot_bodies[f])
            dofs = self.foot_dofs[f]
            foot_torque = jacr[:, dofs] @ tau[dofs]
            artificial[f], ratio = compensation(foot_torque, self.foot)
            ratios.append(ratio)
        if min(ratios) < self.settings.tolerance:
            return np.zeros(model.nv), 0.0
        magnitude = 0.0
        for f, torque_f in artificial.items():
            data.xfrc_applied[self.foot_bodies[f], 3:] = torque_f
            magnitude += float(np.linalg.norm(torque_f))
        return tau, magnitude

    def _push_bodies(self, pushes: Sequence[Push]) -> list[int]:
        """Body id of each push; a body the character does not have is a UserInputError."""
        ids = [mujoco.mj_name2id(self.model, mujoco.mjtObj.mjOBJ_BODY, p.body) for p in pushes]
        for push, body in zip(pushes, ids):
            if body < 0:
                raise UserInputError(
                    f"the push names body '{push.body}', which the character does not have.", field="push"
                )
        return ids

    def _apply_pushes(self, pushes: Sequence[Push], bodies: list[int], t: float) -> None:
        """Set the external forces (N, world) of the pushes active at time t (s); all others are zero."""
        self.data.xfrc_applied[:, :3] = 0.0
        for push, body in zip(pushes, bodies):
            if push.time_s <= t < push.time_s + PUSH_DURATION:
                self.data.xfrc_applied[body, :3] += push.force

    def run(self, duration_s: float | None = None, pushes: Sequence[Push] = ()) -> TrackingResult:
        """Simulate from the reference's first frame for duration_s (default: the whole reference), with the
        given pushes."""
        model, data, ref = self.model, self.data, self.reference
        duration = ref.duration if duration_s is None else min(duration_s, ref.duration)
        data.qpos[:] = ref.qpos[0]
        data.qvel[:] = ref.qvel[0]
        mujoco.mj_forward(model, data)
        push_bodies = self._push_bodies(pushes)
        dt = model.opt.timestep * self.settings.control_every
        steps = int(round(duration / dt))
        joint_err, com_err, torques, qpos_log = [], [], [], [ref.qpos[0].copy()]
        next_record = ref.frame_time
        fell_at = None
        for k in range(steps):
            t = data.time
            target = self._reference_at(t)
            mujoco.mj_forward(model, data)
            forces = self._stance_forces()
            tau_pd = self._pd(target)
            tau_eq, artificial = self._balance(target, forces)
            data.ctrl[: self.world.nmotor] = (tau_pd + tau_eq)[self.joint_dofs]
            self._apply_pushes(pushes, push_bodies, t)
            joint_err.append(quat_angle(data.qpos[self.ball_qpos], target["qpos"][self.ball_qpos]))
            com_err.append(np.linalg.norm(data.subtree_com[self.world.root_body] - target["com"]))
            torques.append(artificial)
            step(self.world, data, self.settings.control_every, model)  # a blow-up raises, naming time and body
            com_z = data.subtree_com[self.world.root_body][2]
            up_z = self.world.root.up_z(data.qpos)
            if has_fallen(com_z, target["com"][2], up_z, self._touches_floor_off_feet()):
                fell_at = float(data.time)
                break
            if data.time + 1e-9 >= next_record:
                qpos_log.append(data.qpos.copy())
                next_record += ref.frame_time
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
        )


def track(
    world: World,
    reference: Reference,
    robustness: float,
    settings: TrackerSettings = TrackerSettings(),
    duration_s: float | None = None,
    pushes: Sequence[Push] = (),
) -> TrackingResult:
    """Track `reference` on `world`'s character with the given robustness in [0, 1]."""
    return Tracker(world, reference, robustness, settings).run(duration_s, pushes)


__all__ = ["FootModel", "Push", "Tracker", "TrackerSettings", "TrackingResult", "track"]
