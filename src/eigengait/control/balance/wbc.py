"""Whole-body inverse dynamics: the tracker's `qp` controller.

Each control step solves one bounded least-squares problem (`scipy.optimize.lsq_linear`) over the
joint accelerations q̈ (nv), the contact forces as pyramid coefficients β ≥ 0 (four edges n ± μ t
per contact point, n the floor's normal, a flat floor at z = 0) and, at robustness R > 0, an
artificial torque a on the root (3, root frame). Every task is a weighted row block in acceleration
units (m/s², rad/s²):

* floating base: the root's six rows of M q̈ + h = Σ Jᵀ D β + [0; a], over the body mass, weighted
  BASE_WEIGHT (all but hard): the contact forces and `a` are the only things that move the body;
* landing: a foot the reference has down that touches nothing yet moves over the floor as the
  reference foot does (its contact spheres' centre accelerates at −HOLD_RATE × its horizontal
  velocity relative to the reference foot's), weighted LANDING_WEIGHT;
* lift-off: a foot the reference raises (its lowest sole point above CONTACT_M and rising) whose
  own lowest point, the sole box's corners included (`foot_sole.lowest_sole_point`), is lower than
  the reference's and within LIFT_BELOW_M of the floor: that point's vertical acceleration
  ω_l² (h_ref − z) + 2 ω_l (ḣ_ref − ż), weighted LIFT_WEIGHT, so a foot the reference lifts does not
  skim the floor (the sole's box reaches 2 cm past the toe sphere the reference pivots on);
* held contacts: each contact point of a foot that the reference has on the floor (lowest sole
  point within CONTACT_M), or that carries LOADED of the body weight while the reference foot comes
  down (a landing that comes early), accelerates as −HOLD_RATE × its velocity: it neither slides
  nor sinks; a foot the reference lifts gets no force, so it can leave the floor (planned forces on
  a toe that is leaving whipped the foot);
* COM: c̈ = c̈_ref + ω_c² (c_ref − c) + 2 ω_c (ċ_ref − ċ), and the root's orientation likewise with
  ω_r: only while a contact is held (in flight nothing can change either); in the push-off before a
  reference flight the vertical row weighs TAKEOFF_COM_GAIN times more (`takeoff.py`);
* joints: q̈ = q̈_ref + ω_q² e + 2 ω_q (q̇_ref − q̇), e the joint error (`pd.joint_error`);
* regularization: β small; a weighted ARTIFICIAL_WEIGHT ((1 − R) / R + ARTIFICIAL_FLOOR), so R = 0
  has none and R = 1 gives it cheaply, never for free.

The motor torques are the internal rows τ = M q̈ + h − Σ Jᵀ D β; `a` is applied to the root as an
external torque. Unlike the momentum controller's joint PD, which pulls each joint toward the
reference whatever the feet carry, every task here is traded against the contact forces the feet
can actually give (measured on the corpus: docs/balance.md, "A whole-body QP controller").
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
from scipy.optimize import lsq_linear

from eigengait.control.balance.controller import BalanceRig
from eigengait.control.balance.double_support import CONTACT_M
from eigengait.control.balance.foot_sole import lowest_sole_point, sole_geoms
from eigengait.control.balance.pd import joint_error
from eigengait.control.balance.reference import Reference
from eigengait.control.balance.takeoff import TAKEOFF_COM_GAIN, takeoff_windows
from eigengait.sim.world import GRAVITY

BASE_WEIGHT = 1000.0  # floating-base rows (accelerations, m/s²)
HOLD_WEIGHT = 30.0  # held contact points' accelerations
HOLD_RATE = 50.0  # 1/s: a held point's acceleration = −HOLD_RATE × its velocity
COM_WEIGHT = 10.0
ROOT_WEIGHT = 10.0
JOINT_WEIGHT = 1.0
LANDING_WEIGHT = 3.0  # a foot the reference has down that does not touch yet: its ground speed
LIFT_WEIGHT = 10.0  # a foot the reference raises that skims the floor: its lowest point's height
LIFT_BANDWIDTH = 20.0  # ω_l, rad/s
LIFT_BELOW_M = 0.03  # m: the lift-off row acts on a lowest point below this height
FORCE_WEIGHT = 1e-3  # on β (N)
# on the artificial torque (N·m over the body mass), × ((1 − R) / R + ARTIFICIAL_FLOOR)
ARTIFICIAL_WEIGHT = 10.0
# its price at R = 1, as a share of ARTIFICIAL_WEIGHT: a free torque left the root's rows with
# nothing to decide them, and the walks at R = 1 took 176-363 N·m of it with 5.5-7.0° of joint
# error (1.5-2.2° and 101-167 N·m with this floor)
ARTIFICIAL_FLOOR = 0.1
JOINT_BANDWIDTH = 30.0  # ω_q, rad/s
COM_BANDWIDTH = 10.0  # ω_c, rad/s (6: the run and the jump 5.9 and 7.0 cm of COM error)
ROOT_BANDWIDTH = 15.0  # ω_r, rad/s
# a foot that carries this share of the body weight while the reference foot comes down is held
# even where the reference has it in the air (a landing that comes early: the jump's COM error
# 9.2 -> 6.6 cm); holding it as well while the reference lifts it cost the laugh's shuffle steps
# (joint RMS 3.1 -> 4.6°)
LOADED = 0.25
FRICTION = 0.8  # the pyramid's μ, under the floor's 1
EDGES = np.array(
    [[FRICTION, 0.0, 1.0], [-FRICTION, 0.0, 1.0], [0.0, FRICTION, 1.0], [0.0, -FRICTION, 1.0]]
).T  # (3, 4): the pyramid's edges on a flat floor, world frame


@dataclass
class WholeBodyCommand:
    """Motor torques (n_motor, N·m, motor order), the artificial torque on the root (3, N·m,
    root frame) and the total contact force the solution counts on (3, N, world)."""

    torque: np.ndarray
    artificial: np.ndarray
    contact_force: np.ndarray


class WholeBodyQP:
    """The per-step problem for one character and reference (the tracker's model: springs off,
    no joint damping)."""

    def __init__(
        self, model: mujoco.MjModel, rig: BalanceRig, reference: Reference, robustness: float
    ):
        self.model, self.rig, self.reference = model, rig, reference
        self.robustness = float(robustness)
        self.mass = float(model.body_subtreemass[rig.root_body])
        self.qacc_ref = np.gradient(reference.qvel, reference.frame_time, axis=0)
        self.foot_rate = np.gradient(reference.foot_height, reference.frame_time, axis=0)
        self.sole_boxes = {f: sole_geoms(model, g) for f, g in rig.foot_spheres.items()}
        self.takeoff = takeoff_windows(reference.foot_height, reference.frame_time)
        self.joints = np.asarray(rig.joint_dofs)
        self.root_turn = np.asarray(rig.root_dofs)[3:6]
        nv = model.nv
        self._mass_matrix = np.zeros((nv, nv))
        self._jac = np.zeros((3, nv))
        self._com_jac = np.zeros((3, nv))

    def command(
        self, data: mujoco.MjData, target: dict[str, np.ndarray], contacts: dict[str, np.ndarray]
    ) -> WholeBodyCommand:
        """Torques for the state in `data` (after `mj_forward`), the reference sample `target`
        (`Tracker._reference_at`) and the feet's floor contacts (`controller.foot_contacts`)."""
        model, rig, nv = self.model, self.rig, self.model.nv
        body_weight = self.mass * GRAVITY
        i, j, blend = self.reference.frame_at(float(data.time))
        nearest = i if blend < 0.5 else j
        sinking = self.foot_rate[nearest] < 0
        held = [
            (rig.foot_bodies[foot], point[:3])
            for foot, height, sinks in zip(rig.foot_bodies, target["foot_height"], sinking)
            if height <= CONTACT_M or (sinks and contacts[foot][:, 3].sum() >= LOADED * body_weight)
            for point in contacts[foot]
        ]
        jacobians = [self._point_jacobian(data, body, point) for body, point in held]
        n_force = 4 * len(held)
        n_art = 3 if self.robustness > 0 and held else 0
        size = nv + n_force + n_art
        rows: list[np.ndarray] = []
        rhs: list[np.ndarray] = []

        def task(a: np.ndarray, b: np.ndarray, weight: float) -> None:
            rows.append(weight * a)
            rhs.append(weight * b)

        mujoco.mj_fullM(model, data, self._mass_matrix)
        bias = data.qfrc_bias - data.qfrc_passive
        base = np.zeros((6, size))
        base[:, :nv] = self._mass_matrix[:6]
        for k, jac in enumerate(jacobians):
            base[:, nv + 4 * k : nv + 4 * k + 4] = -(jac[:, :6].T @ EDGES)
        if n_art:
            base[3:6, nv + n_force :] = -np.eye(3)
        task(base / self.mass, -bias[:6] / self.mass, BASE_WEIGHT)
        for jac in jacobians:
            hold = np.zeros((3, size))
            hold[:, :nv] = jac
            task(hold, -HOLD_RATE * (jac @ data.qvel), HOLD_WEIGHT)
        qacc_ref = (1 - blend) * self.qacc_ref[i] + blend * self.qacc_ref[j]
        if held:
            vertical = TAKEOFF_COM_GAIN if self.takeoff[nearest] else 1.0
            task(*self._com_task(data, target, size, vertical), COM_WEIGHT)
            task(*self._root_task(data, target, qacc_ref, size), ROOT_WEIGHT)
        held_bodies = {body for body, _ in held}
        for foot, height, velocity in zip(
            rig.foot_bodies, target["foot_height"], target["foot_velocity"]
        ):
            if height <= CONTACT_M and rig.foot_bodies[foot] not in held_bodies:
                task(*self._landing_task(data, foot, velocity, size), LANDING_WEIGHT)
        for k, (foot, height) in enumerate(zip(rig.foot_bodies, target["foot_height"])):
            rate = self.foot_rate[nearest, k]
            if height > CONTACT_M and rate > 0 and rig.foot_bodies[foot] not in held_bodies:
                lift = self._lift_task(data, foot, height, rate, size)
                if lift is not None:
                    task(*lift, LIFT_WEIGHT)
        joints = np.zeros((len(self.joints), size))
        joints[np.arange(len(self.joints)), self.joints] = 1.0
        task(joints, self._joint_acceleration(data, target, qacc_ref)[self.joints], JOINT_WEIGHT)
        if n_force:
            forces = np.zeros((n_force, size))
            forces[:, nv : nv + n_force] = np.eye(n_force)
            task(forces, np.zeros(n_force), FORCE_WEIGHT)
        if n_art:
            art = np.zeros((3, size))
            art[:, nv + n_force :] = np.eye(3)
            share = (1.0 - self.robustness) / self.robustness + ARTIFICIAL_FLOOR
            price = ARTIFICIAL_WEIGHT * share / self.mass
            task(art, np.zeros(3), price)
        lower = np.full(size, -np.inf)
        lower[nv : nv + n_force] = 0.0
        x = lsq_linear(
            np.vstack(rows),
            np.concatenate(rhs),
            bounds=(lower, np.full(size, np.inf)),
            method="bvls",
        ).x
        tau = self._mass_matrix @ x[:nv] + bias
        forces = (EDGES @ x[nv : nv + n_force].reshape(-1, 4).T).T  # (contacts, 3)
        for jac, force in zip(jacobians, forces):
            tau -= jac.T @ force
        artificial = x[nv + n_force :] if n_art else np.zeros(3)
        return WholeBodyCommand(tau[self.joints], artificial, forces.sum(axis=0))

    def _point_jacobian(self, data: mujoco.MjData, body: int, point: np.ndarray) -> np.ndarray:
        mujoco.mj_jac(self.model, data, self._jac, None, point, body)
        return self._jac.copy()

    def _landing_task(self, data, foot, reference_velocity, size) -> tuple[np.ndarray, np.ndarray]:
        """A foot the reference has down that does not touch yet moves over the floor as the
        reference foot does (`reference_velocity`, (2,) m/s; zero for a cleaned reference's planted
        foot): the centre of its contact spheres accelerates horizontally at −HOLD_RATE × the
        difference. (Bringing it down as well, ω_q² × its height, threw the walks' steps off:
        05_01's joint error 1.6° → 15°.)"""
        spheres = self.rig.foot_spheres[foot]
        centre = data.geom_xpos[spheres].mean(axis=0)
        jac = self._point_jacobian(data, self.rig.foot_bodies[foot], centre)[:2]
        a = np.zeros((2, size))
        a[:, : self.model.nv] = jac
        return a, -HOLD_RATE * (jac @ data.qvel - reference_velocity)

    def _lift_task(self, data, foot, height, rate, size) -> tuple[np.ndarray, np.ndarray] | None:
        """The lift-off row (module doc) of a foot the reference raises to `height` (m) at `rate`
        (m/s); None when the foot's lowest point is already as high, or above LIFT_BELOW_M."""
        point = lowest_sole_point(
            self.model, data, self.rig.foot_spheres[foot], self.sole_boxes[foot]
        )
        if point[2] >= min(height, LIFT_BELOW_M):
            return None
        jac = self._point_jacobian(data, self.rig.foot_bodies[foot], point)[2:3]
        w = LIFT_BANDWIDTH
        acc = w * w * (height - point[2]) + 2 * w * (rate - float(jac[0] @ data.qvel))
        a = np.zeros((1, size))
        a[:, : self.model.nv] = jac
        return a, np.array([acc])

    def _com_task(self, data, target, size, vertical: float) -> tuple[np.ndarray, np.ndarray]:
        """The COM rows, the vertical one weighted `vertical` times."""
        root, w = self.rig.root_body, COM_BANDWIDTH
        mujoco.mj_jacSubtreeCom(self.model, data, self._com_jac, root)
        mujoco.mj_subtreeVel(self.model, data)
        com, com_vel = data.subtree_com[root], data.subtree_linvel[root]
        acc = (
            target["com_acc"]
            + w * w * (target["com"] - com)
            + 2 * w * (target["com_vel"] - com_vel)
        )
        a = np.zeros((3, size))
        a[:, : self.model.nv] = self._com_jac
        scale = np.array([1.0, 1.0, vertical])
        return scale[:, None] * a, scale * acc

    def _root_task(self, data, target, qacc_ref, size) -> tuple[np.ndarray, np.ndarray]:
        adr, turn, w = self.rig.root_qpos + 3, self.root_turn, ROOT_BANDWIDTH
        error = joint_error(data.qpos[None, adr : adr + 4], target["qpos"][None, adr : adr + 4])[0]
        acc = qacc_ref[turn] + w * w * error + 2 * w * (target["qvel"][turn] - data.qvel[turn])
        a = np.zeros((3, size))
        a[np.arange(3), turn] = 1.0
        return a, acc

    def _joint_acceleration(self, data, target, qacc_ref) -> np.ndarray:
        rig, w = self.rig, JOINT_BANDWIDTH
        error = np.zeros(self.model.nv)
        if len(rig.ball_qpos):
            error[rig.ball_dof] = joint_error(
                data.qpos[rig.ball_qpos], target["qpos"][rig.ball_qpos]
            )
        if len(rig.hinge_qpos):
            error[rig.hinge_dof] = target["qpos"][rig.hinge_qpos] - data.qpos[rig.hinge_qpos]
        return qacc_ref + w * w * error + 2 * w * (target["qvel"] - data.qvel)
