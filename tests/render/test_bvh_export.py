import mujoco
import numpy as np

from eigengait.character import load_character
from eigengait.modal import compute_modes
from eigengait.motion.bvh import end_site_positions, global_transforms, read_bvh
from eigengait.motion.bvh_export import (
    MUJOCO_TO_BVH,
    UNIT_SCALE,
    anchor_points,
    skeleton_bodies,
    write_trajectory_bvh,
)
from eigengait.motion.modal_mix import ModeTerm, build_mix, mix_trajectory
from eigengait.sim.world import WorldOptions, build_world


def _random_mix_round_trip(world, modes, tmp_path, seed):
    rng = np.random.default_rng(seed)
    chosen = rng.choice(modes.count, size=4, replace=False) + 1
    terms = [
        ModeTerm(int(k), float(rng.uniform(0.5, 2.0)), float(rng.uniform(0, 360))) for k in chosen
    ]
    _, qpos = mix_trajectory(world, build_mix(world, modes, terms), seconds=0.5, fps=24)
    path = tmp_path / "mix.bvh"
    write_trajectory_bvh(world, qpos, 24, path, units="cm")
    return qpos, read_bvh(path)


def _mujoco_points_in_bvh_units(world, qpos, bodies):
    data = mujoco.MjData(world.model)
    points = []
    for q in qpos:
        data.qpos[:] = q
        mujoco.mj_kinematics(world.model, data)
        points.append(anchor_points(world, data, bodies) @ MUJOCO_TO_BVH.T * UNIT_SCALE["cm"])
    return np.array(points)


def test_bvh_forward_kinematics_matches_mujoco_bodies(tmp_path):
    world = build_world(load_character("humanoid"), "crouched", WorldOptions(gravity=False))
    modes = compute_modes(world, "ground")
    qpos, clip = _random_mix_round_trip(world, modes, tmp_path, seed=7)
    bodies = skeleton_bodies(world)
    body_names = [world.model.body(b).name for b in bodies]
    assert sorted(j.name for j in clip.joints) == sorted(body_names + ["left_foot", "right_foot"])
    assert len(clip.joints[0].channels) == 6 and all(len(j.channels) == 3 for j in clip.joints[1:])
    assert abs(clip.frame_time - 1 / 24) < 1e-9 and clip.n_frames == len(qpos)
    _, positions = global_transforms(clip)
    positions = positions[:, [clip.joint_index(name) for name in body_names]]
    expected = _mujoco_points_in_bvh_units(world, qpos, bodies)
    assert np.abs(positions - expected).max() / UNIT_SCALE["cm"] < 1e-4
    # The motion is real: joints move by centimetres, so the comparison above can fail.
    assert np.ptp(positions, axis=0).max() > 2.0


def test_bvh_is_y_up_in_centimetres_with_end_sites_at_leaf_tips(tmp_path):
    world = build_world(load_character("humanoid"), "default", WorldOptions(gravity=False))
    qpos, clip = _random_mix_round_trip(world, compute_modes(world, "air"), tmp_path, seed=3)
    rotations, positions = global_transforms(clip)
    data = mujoco.MjData(world.model)
    data.qpos[:] = qpos[5]
    mujoco.mj_kinematics(world.model, data)
    root = world.root_body
    # height is BVH y
    np.testing.assert_allclose(positions[5, 0, 1], data.xpos[root, 2] * 100, atol=1e-6)
    forearm = clip.joint_index("left_forearm")
    tips = end_site_positions(clip, rotations, positions)
    body = world.model.body("left_forearm").id
    # box bottom face
    tip_world = data.xpos[body] + data.xmat[body].reshape(3, 3) @ np.array([0, 0, -0.26])
    np.testing.assert_allclose(tips[forearm][5], MUJOCO_TO_BVH @ tip_world * 100, atol=1e-5)
    leaves = {j.name for j in clip.joints if j.end_site is not None}
    assert leaves == {"head", "left_forearm", "right_forearm", "left_foot", "right_foot"}
    toe = world.model.site("left_toe").id
    np.testing.assert_allclose(
        tips[clip.joint_index("left_foot")][5], MUJOCO_TO_BVH @ data.site_xpos[toe] * 100, atol=1e-5
    )
