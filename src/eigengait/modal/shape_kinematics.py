"""Mode shapes as joint motion: rotation angles, amplitude rules and displaced poses about the relax
pose.

Units and frames:

* φ_i are the ModeSet's mass-normalized shapes (φᵀMφ = 1) in MuJoCo velocity coordinates, so an
  amplitude A_i is a modal coordinate in √kg·m (equivalently, A_i² is twice the kinetic energy per
  ω_i², in kg·m²).
* A displacement d (nv) is applied to the relax pose with `mj_integratePos(qpos0, d, 1)`: root
  translation in world metres, root and ball-joint rotations as rotation vectors in radians.
* The equal-energy rule E = ½ k_i A_i² with k_i = ω_i² (unit modal mass) gives every mode the same
  energy, so A_i ∝ 1/ω_i and low modes swing wider. The common energy is set so that the mode with
  the largest joint rotation at that energy turns its joint by `max_rotation_deg`; no single mode
  turns any joint further.
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.modal.modeset import ModeSet
from eigengait.sim.world import World

DEFAULT_MAX_ROTATION_DEG = 25.0


def joint_rotations(world: World, displacement: np.ndarray) -> np.ndarray:
    """Rotation angle (rad) of each internal joint for displacements (nv × k) → (n_joints × k)."""
    model = world.model
    d = displacement.reshape(model.nv, -1)
    angles = []
    for j in world.internal_qpos_joints:
        adr = model.jnt_dofadr[j]
        n = 3 if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL else 1
        angles.append(np.linalg.norm(d[adr : adr + n], axis=0))
    return np.array(angles)


def equal_energy_amplitudes(
    world: World, modes: ModeSet, max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG
) -> np.ndarray:
    """Default amplitude of every mode (√kg·m): A_i = c/ω_i, c such that the widest mode reaches the
    angle."""
    omega = 2 * np.pi * modes.frequencies_hz
    peak = joint_rotations(world, modes.shapes / omega).max(axis=0)
    return np.deg2rad(max_rotation_deg) / peak.max() / omega


def peak_rotation_amplitudes(
    world: World, modes: ModeSet, max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG
) -> np.ndarray:
    """Amplitude of each mode (√kg·m) that turns its most-moving joint by exactly the angle (for
    display)."""
    peak = joint_rotations(world, modes.shapes).max(axis=0)
    return np.deg2rad(max_rotation_deg) / peak


def displaced_qpos(world: World, displacement: np.ndarray) -> np.ndarray:
    """Relax pose moved by generalized displacements (T × nv) → qpos (T × nq)."""
    model = world.model
    frames = np.tile(model.qpos0, (len(displacement), 1))
    for qpos, d in zip(frames, displacement):
        mujoco.mj_integratePos(model, qpos, d, 1.0)
    return frames
