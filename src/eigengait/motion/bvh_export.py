"""A World's qpos trajectory as a BVH clip (one BVH joint per body), for Blender and other animation tools.

Axes and units: BVH (x, y, z) = (x, z, −y) of MuJoCo's z-up world, in centimetres. That axis map is the inverse of
Blender's default BVH import (forward −Z, up Y), so the clip lands in Blender exactly where it stands in MuJoCo;
centimetres are the unit of most motion-capture BVH (import into Blender with Scale 0.01 to get metres).

Skeleton: each body's BVH joint sits at its MuJoCo joint anchor (the body origin for the root and for bodies
without a joint). The rest pose (all channels zero) is the relax pose, so offsets are the relax-pose vectors from
parent anchor to child anchor; the root has 6 channels (absolute position, then ZXY rotation), the other joints
3 (ZXY). Each leaf body gets an End Site at the tip of its first box: the face centre farthest from its anchor.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
from scipy.spatial.transform import Rotation

from eigengait.errors import UserInputError
from eigengait.motion.bvh import BvhClip, BvhJoint, write_bvh
from eigengait.sim.world import World

CENTIMETRES_PER_METRE = 100.0
MUJOCO_TO_BVH = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # rows: BVH x, y, z
ROOT_CHANNELS = ["Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"]
JOINT_CHANNELS = ["Zrotation", "Xrotation", "Yrotation"]
EULER_ORDER = "ZXY"  # intrinsic, matching the channel order above


def skeleton_bodies(world: World) -> list[int]:
    """Body ids of the character in MuJoCo's depth-first order (parents before children), root first."""
    model = world.model
    bodies = [b for b in range(model.nbody) if _is_in_subtree(model, b, world.root_body)]
    for b in bodies[1:]:
        for j in range(model.body_jntadr[b], model.body_jntadr[b] + model.body_jntnum[b]):
            if model.jnt_type[j] in (mujoco.mjtJoint.mjJNT_FREE, mujoco.mjtJoint.mjJNT_SLIDE):
                raise UserInputError(f"body '{model.body(b).name}' has a sliding or free joint, which BVH cannot hold",
                                     field="joints", fix="BVH export supports ball and hinge joints below the root")
    return bodies


def _is_in_subtree(model: mujoco.MjModel, body: int, root: int) -> bool:
    while body > 0:
        if body == root:
            return True
        body = int(model.body_parentid[body])
    return False


def anchor_points(world: World, data: mujoco.MjData, bodies: list[int]) -> np.ndarray:
    """World positions (m) of each body's first joint anchor, or its origin if it has no joint (len(bodies) × 3)."""
    model = world.model
    return np.array([data.xanchor[model.body_jntadr[b]] if model.body_jntnum[b] else data.xpos[b] for b in bodies])


def _local_anchor(model: mujoco.MjModel, body: int) -> np.ndarray:
    return model.jnt_pos[model.body_jntadr[body]] if model.body_jntnum[body] else np.zeros(3)


def _leaf_tip(model: mujoco.MjModel, body: int) -> np.ndarray | None:
    """Tip of the body's first box in the body frame: its face centre farthest from the anchor (m)."""
    geoms = [g for g in range(model.body_geomadr[body], model.body_geomadr[body] + model.body_geomnum[body])
             if not model.geom(g).name.startswith("contact:")]
    boxes = [g for g in geoms if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX]
    if boxes:
        g = boxes[0]
        axes = _quat_matrix(model.geom_quat[g])
        faces = model.geom_pos[g] + np.concatenate([axes * model.geom_size[g], -axes * model.geom_size[g]], axis=1).T
    elif geoms:
        faces = model.geom_pos[geoms]
    else:
        return None
    return faces[np.argmax(np.linalg.norm(faces - _local_anchor(model, body), axis=1))]


def _quat_matrix(quat: np.ndarray) -> np.ndarray:
    mat = np.zeros(9)
    mujoco.mju_quat2Mat(mat, quat)
    return mat.reshape(3, 3)


def trajectory_to_clip(world: World, qpos: np.ndarray, fps: float) -> BvhClip:
    """BVH clip of a qpos trajectory (T × nq) sampled at `fps` frames per second (axes and units: module doc)."""
    model = world.model
    qpos = np.atleast_2d(qpos)
    if qpos.shape[1] != model.nq:
        raise UserInputError(f"trajectory has {qpos.shape[1]} coordinates per frame, the model {model.nq}",
                             field="qpos")
    bodies = skeleton_bodies(world)
    parent_index = {b: i for i, b in enumerate(bodies)}
    data = mujoco.MjData(model)

    def pose(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        return anchor_points(world, data, bodies), data.xmat[bodies].reshape(-1, 3, 3).copy()

    rest_points, rest_rot = pose(model.qpos0)
    scale = CENTIMETRES_PER_METRE * MUJOCO_TO_BVH
    joints = []
    for i, b in enumerate(bodies):
        parent = -1 if i == 0 else parent_index[int(model.body_parentid[b])]
        offset = np.zeros(3) if parent < 0 else scale @ (rest_points[i] - rest_points[parent])
        is_leaf = not any(int(model.body_parentid[c]) == b for c in bodies[1:])
        tip = _leaf_tip(model, b) if is_leaf else None
        end_site = None if tip is None else scale @ rest_rot[i] @ (tip - _local_anchor(model, b))
        joints.append(BvhJoint(name=model.body(b).name or f"body{b}", parent=parent, offset=offset,
                               channels=ROOT_CHANNELS if parent < 0 else JOINT_CHANNELS, end_site=end_site))

    frames = np.zeros((len(qpos), 3 + 3 * len(bodies)))
    for t, q in enumerate(qpos):
        points, rot = pose(q)
        # Each body's rotation away from its relax orientation, expressed in BVH axes.
        rel = MUJOCO_TO_BVH @ rot @ rest_rot.transpose(0, 2, 1) @ MUJOCO_TO_BVH.T
        local = np.array([rel[0]] + [rel[joints[i].parent].T @ rel[i] for i in range(1, len(bodies))])
        frames[t, :3] = scale @ points[0]
        frames[t, 3:] = Rotation.from_matrix(local).as_euler(EULER_ORDER, degrees=True).ravel()
    frames[:, 3:] = np.rad2deg(np.unwrap(np.deg2rad(frames[:, 3:]), axis=0))
    return BvhClip(joints=joints, frame_time=1.0 / fps, frames=frames)


def write_trajectory_bvh(world: World, qpos: np.ndarray, fps: float, path: str | Path) -> BvhClip:
    """Convert a qpos trajectory (T × nq, at `fps`) with :func:`trajectory_to_clip` and write it to `path`."""
    clip = trajectory_to_clip(world, qpos, fps)
    write_bvh(clip, path)
    return clip
