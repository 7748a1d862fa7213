"""A hand on the root that catches a falling body, for optimization only.

After Yu, Turk & Liu (2018, "Learning symmetric and low-energy locomotion"), whose curriculum holds
the pelvis with a virtual assistant and weakens it as the controller learns: hardening can start a
gait that falls under such a hand and loosen it whenever its candidates survive
(`optimize/survival.py`), so the search always has survivors to rank. It is never part of a played
gait, and it leaves a body alone while it moves within the targets' bounds:

* a moment (world frame) τ = k (θ − θ₀) n − c ω_h once the root's up axis (its zero pose's, turned
  by its current orientation) leans θ > θ₀ = `MAX_TILT_DEG` (the targets') from world z; n the
  unit axis that turns it back, ω_h the horizontal part of the root's angular velocity (heading
  stays free);
* a lift F = k_z (z₀ − z) − c_z v_z once the root sinks below z₀ = `FREE_HEIGHT_SHARE` of its
  height in the model's zero pose (the biped's fall is a collapse more often than a topple).

At `level` 1, k = m g h per radian (it cancels gravity's toppling moment) and k_z carries the whole
body's weight when the root has sunk by a further 0.3 z₀ (m the body's mass, h its standing COM
height). Each damping is `DAMPING_SHARE` × its stiffness × √(h / g): the forces are read every
10 ms and held in between, like the feedback, and heavier damping held that long kicks the body.
They are applied as generalized forces on the free root: the lift on its vertical translation
(world frame), the moment on its rotational degrees of freedom (the root body's frame).
"""

from __future__ import annotations

import numpy as np

from eigengait.control.gait_targets import MAX_TILT_DEG
from eigengait.errors import UserInputError
from eigengait.geometry import quat_to_mat
from eigengait.sim.root import root_layout
from eigengait.sim.world import GRAVITY, World

FREE_HEIGHT_SHARE = 0.8  # of the root's zero-pose height
LIFT_SPAN = 0.3  # of z₀: the further sinking over which the lift grows to the body's weight
DAMPING_SHARE = 0.1


class RootAssist:
    """The hand at one `level` (≥ 0) for one world's free root."""

    def __init__(self, world: World, level: float):
        model = world.model
        self.layout = root_layout(model, int(model.jnt_bodyid[0]))
        if self.layout.kind != "free":
            raise UserInputError(
                "the hand on the root holds a free root, and this character's root is planar",
                field="assist",
                fix="harden it without --assist",
            )
        h, weight = world.standing_com_height, world.mass() * GRAVITY
        settle = DAMPING_SHARE * np.sqrt(h / GRAVITY)  # s
        self.stiffness = level * weight * h  # N·m per rad
        self.damping = self.stiffness * settle  # N·m·s per rad
        self.free_angle = np.radians(MAX_TILT_DEG)
        self.low = FREE_HEIGHT_SHARE * float(model.qpos0[self.layout.height_qpos])  # m
        self.lift = level * weight / (LIFT_SPAN * self.low)  # N per m
        self.lift_damping = self.lift * settle  # N·s per m
        # the free joint's vertical translation, then its three rotations
        self.first_qvel = self.layout.vertical_qvel
        self.view = world.view

    def forces(self, states: np.ndarray) -> np.ndarray:
        """Generalized forces (candidates × 4: N on the root's vertical translation, then N·m about
        the root body's axes) for full physics `states` (candidates × nstate)."""
        qpos, qvel = self.view.qpos(states), self.view.qvel(states)
        lay = self.layout
        a = lay.quat_qpos
        body = quat_to_mat(qpos[:, a : a + 4])  # root frame -> world
        up = quat_to_mat(lay.upright_quat(qpos))[:, :, 2]
        axis = np.cross(up, [0.0, 0.0, 1.0])
        sin = np.linalg.norm(axis, axis=1)
        past = np.clip(np.arctan2(sin, up[:, 2]) - self.free_angle, 0, None)
        n = axis / np.maximum(sin, 1e-12)[:, None]
        w = self.first_qvel + 1
        omega = np.einsum("kij,kj->ki", body, qvel[:, w : w + 3])
        omega[:, 2] = 0.0
        moment = (past > 0)[:, None] * (self.stiffness * past[:, None] * n - self.damping * omega)
        below = np.clip(self.low - qpos[:, lay.height_qpos], 0, None)
        lift = (below > 0) * (self.lift * below - self.lift_damping * qvel[:, lay.vertical_qvel])
        return np.c_[lift, np.einsum("kji,kj->ki", body, moment)]  # moment: world -> root frame
