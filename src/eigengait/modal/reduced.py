"""Modal analysis in the engine's reduced (joint) coordinates: M from `mj_fullM`, K from joint
stiffness.

Coordinates are MuJoCo's velocity coordinates at the relax pose: the root's free joint (linear
velocity in world, angular velocity in the root frame) followed by each joint's dofs (ball: relative
angular velocity in the child body's frame; hinge: angle rate). K is block-diagonal with
diag(kx, ky, kz) per ball joint and zero on the root.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.sim.world import World


def mass_matrix(world: World) -> np.ndarray:
    """Generalized mass matrix (nv × nv) at the relax pose, kg and kg·m²."""
    data = world.new_data()
    M = np.zeros((world.model.nv, world.model.nv))
    mujoco.mj_fullM(world.model, data, M)
    return M


def stiffness_matrix(world: World) -> np.ndarray:
    """Joint stiffness (nv × nv) in N·m/rad, zero on the root dofs."""
    K = np.zeros((world.model.nv, world.model.nv))
    K[world.internal_qvel, world.internal_qvel] = world.dof_stiffness
    return K


def point_jacobian(world: World, site: str) -> np.ndarray:
    """Translational Jacobian (3 × nv) of a site's world position at the relax pose."""
    data = world.new_data()
    jacp = np.zeros((3, world.model.nv))
    mujoco.mj_jacSite(world.model, data, jacp, None, world.model.site(site).id)
    return jacp
