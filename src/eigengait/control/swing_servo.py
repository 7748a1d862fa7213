"""Swing-foot servo: slows a foot that nears the floor and lifts one that skims it.

For each foot whose lowest contact sphere has its bottom above the floor but within a band c (a
share of the standing COM height h), a force F = m a acts on that sphere's centre through the
leg's own joints (τ = Jᵀ F, the leg being the bodies on that foot's chain, below the root, and on
no other foot's):

    a_xy = −2 ω v_xy (1 − z / c)                              damps the ground speed as it lands
    a_z  = l ω² (c − z) · min(1, |v_xy| / (0.1 √(g h)))       lifts a foot that moves while low

with z the sphere bottom's height, v its velocity (world frame, m/s) and m the leg's mass. A foot
on the floor or above the band gets nothing. The torques are read at one state and held, as the
feedback's are, for 10 ms.
"""

from __future__ import annotations

from typing import NamedTuple

import mujoco
import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from eigengait.body_tree import ancestors
from eigengait.sim.world import GRAVITY, World


class ServoSettings(BaseModel):
    """The servo's three numbers, as sketches and controller files write them (`swing_servo:`)."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False, frozen=True)
    band: float = Field(0.06, gt=0, le=0.5, description="c, a share of the standing COM height")
    omega: float = Field(4.0, gt=0, le=20, description="ω, in units of √(g / h)")
    lift: float = Field(0.25, ge=0, le=4, description="l: 0 damps without lifting")


class ServoLeg(NamedTuple):
    """One foot's leg as the servo drives it."""

    sites: list[int]  # the foot's contact-sphere centre sites (toe, heel)
    body: int  # the body those sites are on
    radius: float  # m, the spheres' radius
    dofs: np.ndarray  # qvel indices of the leg's joints
    motors: np.ndarray  # the same joints' motor indices
    mass: float  # kg, the leg's mass


class SwingServo:
    """Torques (N·m, motor order) of the swing-foot servo for batches of full-physics states."""

    def __init__(self, world: World, settings: ServoSettings = ServoSettings()):
        model = world.model
        self.world, self.model = world, model
        self.data = mujoco.MjData(model)
        h = world.standing_com_height
        self.band = settings.band * h
        self.omega = settings.omega * np.sqrt(GRAVITY / h)
        self.lift = settings.lift
        self.slow = 0.1 * np.sqrt(GRAVITY * h)  # m/s: ground speed at which the lift is full
        motor_of_dof = {int(d): k for k, d in enumerate(world.internal_qvel)}
        chains = {
            foot: set(ancestors(model, model.site(world.character.feet[foot].toe).bodyid[0]))
            for foot in world.character.feet
        }
        self.legs: list[ServoLeg] = []
        for foot, chain in chains.items():
            others = set().union(*(c for f, c in chains.items() if f != foot))
            leg_bodies = chain - others - {world.root_body}
            dofs = [
                d
                for d in range(model.nv)
                if model.dof_bodyid[d] in leg_bodies and d in motor_of_dof
            ]
            top = min(leg_bodies, key=lambda b: len(list(ancestors(model, b))))
            sites = [
                model.site(s).id
                for s in (world.character.feet[foot].toe, world.character.feet[foot].heel)
                if s
            ]
            self.legs.append(
                ServoLeg(
                    sites=sites,
                    body=int(model.site(sites[0]).bodyid[0]),
                    radius=world.foot_radius(foot),
                    dofs=np.array(dofs),
                    motors=np.array([motor_of_dof[d] for d in dofs]),
                    mass=float(model.body_subtreemass[top]),
                )
            )
        self.jacp = np.zeros((3, model.nv))

    def torque(self, states: np.ndarray) -> np.ndarray:
        """Servo torques (… × n_motor) for full-physics states (… × state size)."""
        shape = states.shape[:-1]
        flat = states.reshape(-1, states.shape[-1])
        view = self.world.view
        qpos, qvel = view.qpos(flat), view.qvel(flat)
        out = np.zeros((flat.shape[0], self.world.nmotor))
        model, data = self.model, self.data
        for r in range(flat.shape[0]):
            data.qpos[:], data.qvel[:] = qpos[r], qvel[r]
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            for leg in self.legs:
                heights = data.site_xpos[leg.sites, 2] - leg.radius
                lowest = int(np.argmin(heights))
                z = float(heights[lowest])
                if not 0.0 < z < self.band:
                    continue
                point = data.site_xpos[leg.sites[lowest]]
                mujoco.mj_jac(model, data, self.jacp, None, point, leg.body)
                v = self.jacp @ qvel[r]
                speed = float(np.hypot(v[0], v[1]))
                a = np.empty(3)
                a[:2] = -2.0 * self.omega * v[:2] * (1.0 - z / self.band)
                a[2] = self.lift * self.omega**2 * (self.band - z) * min(1.0, speed / self.slow)
                out[r, leg.motors] += self.jacp[:, leg.dofs].T @ (leg.mass * a)
        return out.reshape(*shape, self.world.nmotor)
