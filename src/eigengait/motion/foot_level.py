"""Level the retargeted feet: the foot stands flat when the clip's foot stands still on the floor.

The retarget's rest offset assumes that the clip's rest pose (all rotations zero) holds the sole
level. Skeletons disagree (a foot bone's rest direction says nothing of the sole, whose toe may
point down or out), so a stance foot can stand on its toe or heel edge throughout the clip: measured
on the CMU clips, a median stance pitch of −4° to −15° (heel raised). A physical foot then rests
flat and tips the whole body by that angle.

Per foot, the still frames are those in which the lowest sole point is within STILL_HEIGHT_M of the
floor and the sole centre moves slower than STILL_SPEED horizontally; the world up direction seen in
the foot's own frame is averaged over them (v̄) and compared with the rest pose's (v⁰, the foot level
in the character's relax pose). The foot's orientation gets the constant correction C = min_arc(v⁰,
v̄) in its own frame in every frame (W ← W C: then W C v⁰ = W v̄ ≈ up when still), i.e. its ball
joint's rotation q ← q C. Heel-off and toe-off keep their motion relative to the levelled stance.
A foot on two or three hinges (dm_control's ankles) gets the hinge angles nearest its corrected
turn (`hinge_chain`); a foot on one hinge, or with fewer than MIN_STILL_S of still frames, is left
as it is. The rest pose's level is the foot's `sole_up`. On
request (`track --levelling flat`) a foot is levelled on the clip's own flat frames instead
(`flat_feet`): right for walks, whose references then stand flat where the clip's feet do, but the
tracker holds most runs better from the still-frame levelling (docs/balance.md).
"""

from __future__ import annotations

import mujoco
import numpy as np

from eigengait.body_tree import body_hinges
from eigengait.geometry import mat_to_quat, min_arc, quat_mul, quat_to_mat
from eigengait.motion.hinge_chain import hinge_angles
from eigengait.motion.soles import sole_points
from eigengait.sim.feet import foot_up, sole_up
from eigengait.sim.world import World

STILL_HEIGHT_M = 0.02
STILL_SPEED = 0.2  # m/s
MIN_STILL_S = 0.1


def _foot_ball_joint(model: mujoco.MjModel, body: int) -> int | None:
    """The ball joint that turns the foot body, if that is how the foot is attached."""
    joint = int(model.body_jntadr[body])
    if model.body_jntnum[body] == 1 and model.jnt_type[joint] == mujoco.mjtJoint.mjJNT_BALL:
        return joint
    return None


def still_frames(soles: np.ndarray, frame_time: float) -> np.ndarray:
    """Frames (F,) bool in which a foot with sole points (F, k, 3) stands still on the floor."""
    low = soles[..., 2].min(axis=1)
    speed = np.linalg.norm(np.gradient(soles.mean(axis=1)[:, :2], frame_time, axis=0), axis=1)
    return (low <= STILL_HEIGHT_M) & (speed <= STILL_SPEED)


def level_feet(
    world: World, qpos: np.ndarray, frame_time: float, frames: dict[str, np.ndarray] | None = None
) -> tuple[np.ndarray, dict[str, float]]:
    """Poses (F, nq) with levelled feet, and each levelled foot's correction angle (degrees).

    frames: per foot name, the frames (F,) bool to level it on instead of its still frames (the
    clip's own flat frames, `flat_feet`), used when they last MIN_STILL_S."""
    model, data = world.model, mujoco.MjData(world.model)
    soles = sole_points(world, qpos)
    out, angles = qpos.copy(), {}
    for foot, geoms in world.foot_spheres.items():
        body = int(model.geom_bodyid[geoms[0]])
        joint = _foot_ball_joint(model, body)
        hinges = body_hinges(model, body)
        given = (frames or {}).get(foot)
        enough = given is not None and given.sum() * frame_time >= MIN_STILL_S
        still = given if enough else still_frames(soles[foot], frame_time)
        if (joint is None and len(hinges) < 2) or still.sum() * frame_time < MIN_STILL_S:
            continue
        rest_up = sole_up(world, foot)
        mean_up = np.mean(
            [foot_up(model, data, qpos[i], body) for i in np.flatnonzero(still)], axis=0
        )
        mean_up /= np.linalg.norm(mean_up)
        correction = min_arc(rest_up, mean_up)
        if joint is not None:
            adr = model.jnt_qposadr[joint]
            out[:, adr : adr + 4] = quat_mul(qpos[:, adr : adr + 4], mat_to_quat(correction))
        else:
            turns = _turns_from_parent(model, data, qpos, body)
            out[:, model.jnt_qposadr[hinges]] = hinge_angles(
                turns @ correction, model.jnt_axis[hinges]
            )
        angles[foot] = float(np.degrees(np.arccos(np.clip(rest_up @ mean_up, -1.0, 1.0))))
    return out, angles


def _turns_from_parent(
    model: mujoco.MjModel, data: mujoco.MjData, qpos: np.ndarray, body: int
) -> np.ndarray:
    """The body's rotation (F, 3, 3) relative to its parent's frame moved by the body's fixed
    offset (the turn its own joints make) in each pose of qpos (F, nq)."""
    parent, local = int(model.body_parentid[body]), quat_to_mat(model.body_quat[body])
    turns = np.empty((len(qpos), 3, 3))
    for i, q in enumerate(qpos):
        data.qpos[:] = q
        mujoco.mj_kinematics(model, data)
        frame = data.xmat[parent].reshape(3, 3) @ local
        turns[i] = frame.T @ data.xmat[body].reshape(3, 3)
    return turns


__all__ = ["level_feet", "still_frames"]
