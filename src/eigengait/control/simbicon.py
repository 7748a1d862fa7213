"""SIMBICON's balance layer (Yin, Loken & van de Panne 2007) under the pulses.

Two proportional-derivative laws act in the character's **heading frame** (world z up, x along the
root body's forward axis projected on the floor), read every 10 ms and held, as the feedback's are:

* **Swing foot placement.** The swing thigh (hip to knee) is driven toward a direction that leans
  φ forward and ψ sideways from straight down,

      φ = φ₀ + c_d d_x + c_v (v_x − v*),    ψ = c_d d_y + c_v v_y,

  with d the COM's horizontal offset from the support toe (over the standing COM height h), v the
  COM velocity (over √(g h)) and v* the target speed: a body ahead of its foot or too fast places
  the next foot further forward. The torque k_p (u × u_d) − k_d ω⊥ acts on the thigh (u its
  direction, ω⊥ its angular velocity without the twist about u).
* **Torso.** In a ground state the stance hip holds the root's up axis at a forward lean λ:
  τ_torso = k_p,t (z × z_d) − k_d,t ω_xy on the root, given through the stance hip together with
  the swing hip's reaction, τ_stance = −τ_torso − τ_swing.

Gains are shares of m g h per radian (m the body's mass), the damping a time constant times the
stiffness, so one setting fits any character. In an air state only the swing thigh is driven. A leg
is read from the body of its first joint (`feedback.leg_root_joint`) to that body's child on the way
to the foot: a hip on a biped or a hopper, but on a quadruped whose front legs hang from a chest
joint, the chest.
"""

from __future__ import annotations

import mujoco
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from eigengait.body_tree import ancestors
from eigengait.control.feedback import StateRole, leg_root_joint
from eigengait.sim.world import GRAVITY, World

MAX_FORWARD_LEAN = 0.8  # rad: the swing thigh's target φ is clipped to ±this
MAX_SIDEWAYS_LEAN = 0.5  # rad: and ψ to ±this


class SimbiconSettings(BaseModel):
    """The layer's numbers, as sketches and controller files write them (`simbicon:`)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)
    swing: float = Field(0.5, ge=0, le=10, description="k_p of the swing thigh, m g h per rad")
    torso: float = Field(1.0, ge=0, le=10, description="k_p,t of the torso, m g h per rad")
    damping: float = Field(0.1, ge=0, le=1, description="s: k_d = damping × k_p (both laws)")
    placement: float = Field(0.2, ge=-1, le=1, description="φ₀, rad forward")
    offset_gain: float = Field(0.5, ge=0, le=5, description="c_d, rad per unit d / h")
    speed_gain: float = Field(0.6, ge=0, le=5, description="c_v, rad per unit v / √(g h)")
    speed: float = Field(0.0, ge=0, le=20, description="v*, m/s")
    lean: float = Field(0.1, ge=-0.5, le=0.5, description="λ, rad forward")


class SimbiconLayer:
    """Torques (N·m, motor order) of the layer for one full-physics state at a time."""

    def __init__(self, world: World, feet: list[str], settings: SimbiconSettings):
        model = world.model
        self.model, self.view, self.settings = model, world.view, settings
        self.data = mujoco.MjData(model)
        self.n_motor = world.nmotor
        h = world.standing_com_height
        mgh = world.mass() * GRAVITY * h
        self.offset_scale, self.speed_scale = h, np.sqrt(GRAVITY * h)
        self.swing_kp, self.torso_kp = settings.swing * mgh, settings.torso * mgh
        motor_of_dof = {int(d): k for k, d in enumerate(world.internal_qvel)}
        self.root, self.root_layout = world.root_body, world.root
        # foot -> thigh body, shin body, the hip's dofs and their motors
        self.legs: dict[str, tuple[int, int, np.ndarray, list[int]]] = {}
        for foot in dict.fromkeys(feet):
            joint = model.joint(leg_root_joint(world, foot)).id
            thigh = int(model.jnt_bodyid[joint])
            toe = int(model.site(world.character.feet[foot].toe).bodyid[0])
            # the thigh's child on the way to this foot (its knee end)
            shin = next(b for b in ancestors(model, toe) if model.body_parentid[b] == thigh)
            dofs = np.flatnonzero(model.dof_bodyid == thigh)
            self.legs[foot] = (thigh, shin, dofs, [motor_of_dof[int(k)] for k in dofs])

    def torque(self, state: np.ndarray, sensors: np.ndarray, role: StateRole) -> np.ndarray:
        """The layer's torque (n_motor,) for one state and its sensors in a state of `role`."""
        s, m, d = self.settings, self.model, self.data
        mujoco.mj_setState(m, d, state, mujoco.mjtState.mjSTATE_FULLPHYSICS)
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        mujoco.mj_comVel(m, d)
        root = d.xmat[self.root].reshape(3, 3)
        yaw = float(self.root_layout.heading(self.view.qpos(state)))
        cos_yaw, sin_yaw = np.cos(yaw), np.sin(yaw)
        # heading frame -> world
        heading = np.array([[cos_yaw, -sin_yaw, 0.0], [sin_yaw, cos_yaw, 0.0], [0.0, 0.0, 1.0]])
        offset = self.view.com(sensors) - self.view.toe(sensors, role.support)
        d_h = heading.T @ np.r_[offset[:2], 0.0] / self.offset_scale
        v_h = heading.T @ np.r_[self.view.com_velocity(sensors)[:2], 0.0]
        v_h[0] -= s.speed
        v_h /= self.speed_scale
        tau = np.zeros(self.n_motor)
        swing = np.zeros(3)
        if role.swing is not None:
            phi = s.placement + s.offset_gain * d_h[0] + s.speed_gain * v_h[0]
            psi = s.offset_gain * d_h[1] + s.speed_gain * v_h[1]
            phi = np.clip(phi, -MAX_FORWARD_LEAN, MAX_FORWARD_LEAN)
            psi = np.clip(psi, -MAX_SIDEWAYS_LEAN, MAX_SIDEWAYS_LEAN)
            target = heading @ np.array([np.tan(phi), np.tan(psi), -1.0])
            thigh, shin, dofs, motors = self.legs[role.swing]
            swing = self._hold_direction(thigh, d.xpos[shin] - d.xpos[thigh], target, self.swing_kp)
            tau[motors] += d.cdof[dofs, :3] @ swing  # each hip axis's share (world axes)
        if role.stance is not None:
            target = heading @ np.array([np.sin(s.lean), 0.0, np.cos(s.lean)])
            spin = d.cvel[self.root][:3] * np.array([1.0, 1.0, 0.0])
            torso = self.torso_kp * (np.cross(root[:, 2], target) - s.damping * spin)
            _, _, dofs, motors = self.legs[role.stance]
            tau[motors] += d.cdof[dofs, :3] @ (-torso - swing)
        return tau

    def _hold_direction(self, body: int, axis: np.ndarray, target: np.ndarray, kp: float):
        """World torque (3,) turning `body`'s `axis` toward `target`, damped without twist."""
        u, goal = axis / np.linalg.norm(axis), target / np.linalg.norm(target)
        spin = self.data.cvel[body][:3]
        return kp * (np.cross(u, goal) - self.settings.damping * (spin - (spin @ u) * u))
