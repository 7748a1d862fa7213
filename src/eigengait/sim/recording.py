"""Named reads of recorded simulation: the world's MuJoCo full-physics states and sensor readings,
as `mujoco.rollout` returns them and `mj_getState` / `data.sensordata` give them one at a time.

A full-physics state (`mjSTATE_FULLPHYSICS`) is [time (s), qpos (nq), qvel (nv), act (na), …]. The
world's sensordata (`sim/world.py`) is [COM (3, m), COM velocity (3, m/s), then the world position
(3, m) of each foot's contact-sphere centres, toe then heel]. Every accessor reads the last axis and
keeps any leading shape (one row, steps, candidates × steps, …); the slices are views into their
argument, not copies.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from eigengait.sim.contacts import foot_touching
from eigengait.sim.root import RootLayout

if TYPE_CHECKING:
    from eigengait.sim.world import World


@dataclass(frozen=True)
class RolloutView:
    """Where each simulation fact lives in a world's states and sensordata (build it with `of`, or
    use `World.view`)."""

    nq: int
    nv: int
    na: int
    root: RootLayout
    com_at: int  # sensordata address of the whole creature's COM (3)
    com_velocity_at: int  # sensordata address of its COM velocity (3)
    # foot -> sensordata addresses of its sphere centres, toe then heel
    foot_points_at: dict[str, tuple[int, ...]]
    foot_radius: dict[str, float]  # foot -> radius (m) of its contact spheres

    @classmethod
    def of(cls, world: World) -> RolloutView:
        model = world.model
        feet = world.character.feet
        return cls(
            nq=model.nq,
            nv=model.nv,
            na=model.na,
            root=world.root,
            com_at=world.com_sensor,
            com_velocity_at=world.comvel_sensor,
            foot_points_at={f: tuple(world.foot_point_sensors(f)) for f in feet},
            foot_radius={f: world.foot_radius(f) for f in feet},
        )

    # ------------------------------------------------------------------ states (…, state size)
    def time(self, states: np.ndarray) -> np.ndarray:
        """Simulation time (s), shape (…)."""
        return states[..., 0]

    def physics(self, states: np.ndarray) -> np.ndarray:
        """Every entry after the time: qpos, qvel, act and the rest (…, state size − 1)."""
        return states[..., 1:]

    def qpos(self, states: np.ndarray) -> np.ndarray:
        """Generalized positions (…, nq)."""
        return states[..., 1 : 1 + self.nq]

    def qvel(self, states: np.ndarray) -> np.ndarray:
        """Generalized velocities (…, nv)."""
        return states[..., 1 + self.nq : 1 + self.nq + self.nv]

    def act(self, states: np.ndarray) -> np.ndarray:
        """Actuator activations (…, na): the motors' filtered torques (N·m) when the world has an
        activation time."""
        start = 1 + self.nq + self.nv
        return states[..., start : start + self.na]

    def up_z(self, states: np.ndarray) -> np.ndarray:
        """World z of the root's up axis (…): 1 upright, < 0 upside down (`RootLayout.up_z`)."""
        return self.root.up_z(self.qpos(states))

    # ------------------------------------------------------------------ sensors (…, nsensordata)
    def com(self, sensors: np.ndarray) -> np.ndarray:
        """World position (m) of the whole creature's centre of mass (…, 3)."""
        return sensors[..., self.com_at : self.com_at + 3]

    def com_velocity(self, sensors: np.ndarray) -> np.ndarray:
        """World velocity (m/s) of the whole creature's centre of mass (…, 3)."""
        return sensors[..., self.com_velocity_at : self.com_velocity_at + 3]

    def foot_points(self, sensors: np.ndarray, foot: str) -> np.ndarray:
        """World positions (m) of the foot's contact-sphere centres, toe then heel (…, k, 3; a
        copy)."""
        return np.stack([sensors[..., a : a + 3] for a in self.foot_points_at[foot]], axis=-2)

    def toe(self, sensors: np.ndarray, foot: str) -> np.ndarray:
        """World position (m) of the foot's toe sphere centre (…, 3)."""
        a = self.foot_points_at[foot][0]
        return sensors[..., a : a + 3]

    def has_heel(self, foot: str) -> bool:
        return len(self.foot_points_at[foot]) > 1

    def heel(self, sensors: np.ndarray, foot: str) -> np.ndarray:
        """World position (m) of the foot's heel sphere centre (…, 3); the foot must have one
        (`has_heel`)."""
        a = self.foot_points_at[foot][1]
        return sensors[..., a : a + 3]

    def feet_touching(self, sensors: np.ndarray) -> dict[str, np.ndarray]:
        """foot -> (…) bool: one of its contact spheres touches the ground (`sim/contacts.py`)."""
        return {
            f: foot_touching(self.foot_points(sensors, f), r) for f, r in self.foot_radius.items()
        }


def frame_rows(steps: int, timestep: float, fps: float) -> np.ndarray:
    """Frames at t = k / fps (k = 0, 1, …) of a rollout of `steps` physics steps of `timestep` s, as
    row indices into [initial state, state after step 1, …, state after step `steps`]: each frame is
    the nearest step."""
    rows = np.round(np.arange(int(steps * timestep * fps) + 1) / fps / timestep).astype(int)
    return rows[rows <= steps]
