"""Users' MJCF models (dm_control copies in shared/data/models): loading rules and their numbers."""

import json
import re

import mujoco
import numpy as np
import pytest

from eigengait.character import load_character
from eigengait.character.guess import mirror_pairs
from eigengait.character.stiffness import GRAVITY, SAG_DEG
from eigengait.control.sketch import load_sketch
from eigengait.errors import UserInputError
from eigengait.modal import compute_modes
from eigengait.optimize.problem import Problem
from eigengait.sim import build_world
from eigengait.sim.stepping import MAX_SPEED
from shared_data import DM_CONTROL

MODELS = DM_CONTROL
WALKER = MODELS / "suite" / "walker.xml"
# model -> (internal DOF, rigid air modes, guessed feet)
EXPECTED = {
    "suite/humanoid.xml": (21, 6, {"right_foot", "left_foot"}),
    "suite/humanoid_CMU.xml": (56, 6, {"lfoot", "rfoot"}),
    "suite/quadruped.xml": (
        16,
        12,
        {"toe_front_left", "toe_front_right", "toe_back_right", "toe_back_left"},
    ),
    "suite/walker.xml": (6, 3, {"right_foot", "left_foot"}),
    "suite/cheetah.xml": (6, 3, {"bfoot", "ffoot"}),
    "locomotion/humanoid_CMU_V2020.xml": (56, 6, {"lfoot", "rfoot"}),
}


@pytest.mark.parametrize("model", EXPECTED)
def test_model_loads_with_its_modes_and_feet(model):
    dofs, rigid, feet = EXPECTED[model]
    character = load_character(MODELS / model, stiffness="auto")
    assert character.internal_dofs == dofs and set(character.feet) == feet
    air = compute_modes(character)
    assert air.rigid_modes == rigid and air.count == dofs
    assert np.all(np.diff(air.frequencies_hz) >= 0) and air.frequencies_hz[0] > 0


def _capsule_bottom(model, data, geom):
    """Lowest world z (m) of a capsule: its lower end's centre minus its radius."""
    axis = data.geom_xmat[geom].reshape(3, 3)[:, 2] * model.geom_size[geom, 1]
    return min(data.geom_xpos[geom][2] + s * axis[2] for s in (-1, 1)) - model.geom_size[geom, 0]


@pytest.mark.parametrize(
    "model, length, radius",
    [
        ("suite/walker.xml", 0.2, 0.05),
        ("suite/humanoid.xml", 0.21, 0.027),
        ("suite/humanoid_CMU.xml", 0.12, 0.02),
    ],
)
def test_guessed_feet_stand_on_heel_and_toe_at_their_soles_ends(model, length, radius):
    """A capsule foot gets a heel and a toe sphere at its capsules' ends, as low as the capsules'
    own bottoms (the walker's foot is one 0.2 m capsule of radius 0.05; the suite humanoid's two
    side by side, 0.21 m; the CMU humanoid's three, 0.12 m, with its toes a body below the foot),
    the toe in front: toward +x, where the walker faces, or the way the CMU humanoid's toes lie."""
    character = load_character(MODELS / model, stiffness="auto")
    world = build_world(character)
    m, d = world.model, mujoco.MjData(world.model)
    d.qpos[:] = m.qpos0
    mujoco.mj_kinematics(m, d)
    for foot, spheres in world.foot_spheres.items():
        toe, heel = (d.geom_xpos[g] for g in spheres)
        np.testing.assert_allclose(m.geom_size[spheres, 0], radius, atol=1e-6)
        assert np.linalg.norm(toe - heel) == pytest.approx(length, abs=0.01)
        body = int(m.geom_bodyid[spheres[0]])
        capsules = [
            g
            for g in np.flatnonzero(m.geom_bodyid == body)
            if int(m.geom_type[g]) == mujoco.mjtGeom.mjGEOM_CAPSULE
        ]
        sole = min(_capsule_bottom(m, d, g) for g in capsules)
        bottoms = [d.geom_xpos[g][2] - m.geom_size[g, 0] for g in spheres]
        assert min(bottoms) == pytest.approx(sole, abs=1e-9)
        children = [b for b in range(m.nbody) if m.body_parentid[b] == body]
        ahead = d.xpos[children[0]] - heel if children else np.array([1.0, 0, 0])
        assert (toe - heel)[:2] @ ahead[:2] > 0


def test_builtin_planar_walker_is_the_users_walker_with_the_auto_stiffness():
    """The built-in keeps dm_control's file as shipped; its sidecar holds what `--stiffness auto`
    chooses."""
    builtin = load_character("planar-walker")
    assert builtin.path.read_bytes() == WALKER.read_bytes()
    assert builtin.name == "planar-walker" and builtin.meta.strength == 1.0
    users = load_character(WALKER, stiffness="auto")
    assert (
        set(builtin.stiffness) == set(users.stiffness) and builtin.root_joints == users.root_joints
    )
    for joint, k in users.stiffness.items():
        np.testing.assert_allclose(builtin.stiffness[joint], k, rtol=1e-6)
    # the model's own floor strip is kept but not drawn over eigengait's
    model = build_world(builtin).model
    floor = model.geom("floor").id
    assert model.geom_rgba[floor][3] == 0.0 and model.geom_matid[floor] == -1
    assert model.geom_rgba[model.geom("eigengait:floor").id][3] > 0.0


def test_initial_poses_stay_inside_joint_ranges(tmp_path, eigengait_cli):
    """The quadruped's starter sketch: modal initial poses reach beyond its ankles' ranges, and a
    violated limit launched the body within 3 ms. Decoded poses are clipped into every limited
    hinge's range and simulate 10 ms with no torque without blowing up."""
    sketch = tmp_path / "q.yaml"
    made = eigengait_cli(
        "sketch", "new", MODELS / "suite/quadruped.xml", "--stiffness", "auto", "-o", sketch
    )
    assert made.returncode == 0, made.stderr
    problem = Problem.from_sketch(load_sketch(sketch))
    model = problem.system.world.model
    hinges = [
        j
        for j in np.flatnonzero(model.jnt_limited)
        if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_HINGE)
    ]
    for x in np.random.default_rng(0).uniform(0, 1, (8, problem.space.size)):
        p = problem.space.decode(x)
        for j in hinges:
            low, high = model.jnt_range[j]
            assert low <= p.qpos0[model.jnt_qposadr[j]] <= high
        data = mujoco.MjData(model)
        data.qpos[:], data.qvel[:] = p.qpos0, p.qvel0
        mujoco.mj_step(model, data, 20)
        assert np.isfinite(data.qvel).all() and np.abs(data.qvel).max() < MAX_SPEED


def test_planar_root_gives_the_free_root_modes_of_a_planar_creature(tmp_path):
    """The walker with both legs moved into the plane y = 0 has all its mass in that plane and all
    joints about y: with a free root instead of slide x/z + hinge y, only rigid out-of-plane motion
    is added, so the non-rigid frequencies must be the same. (With the legs at y = ±0.05 a swinging
    leg would yaw a free torso.)"""
    spec = mujoco.MjSpec.from_file(str(WALKER))
    for leg in ("left_thigh", "right_thigh"):
        spec.body(leg).pos[1] = 0.0
    in_plane = tmp_path / "walker_in_plane.xml"
    in_plane.write_text(spec.to_xml())
    torso = spec.body("torso")
    for j in list(torso.joints):
        spec.delete(j)
    torso.add_freejoint()
    free_xml = tmp_path / "walker_free.xml"
    free_xml.write_text(spec.to_xml())
    planar = compute_modes(load_character(in_plane, stiffness="auto"))
    free = compute_modes(load_character(free_xml, stiffness="auto"))
    assert (planar.rigid_modes, free.rigid_modes) == (3, 6)
    np.testing.assert_allclose(planar.frequencies_hz, free.frequencies_hz, rtol=1e-6)
    ground = compute_modes(load_character(WALKER, stiffness="auto"), "ground")
    assert ground.rigid_modes == 1  # a pinned toe leaves the rotation about it, in the plane


def test_auto_stiffness_is_the_sag_rule_of_a_point_mass_pendulum(tmp_path):
    m, r = 2.0, 0.4
    path = tmp_path / "pendulum.xml"
    path.write_text(
        '<mujoco><worldbody><body><freejoint/><geom type="box" size=".1 .1 .1" mass="50"/>'
        '<body pos="0 0 -.1"><joint name="hinge" axis="0 1 0"/>'
        f'<geom type="sphere" size=".01" pos="0 0 -{r}" '
        f'mass="{m}"/></body></body></worldbody></mujoco>'
    )
    character = load_character(path, stiffness="auto")
    assert character.stiffness["hinge"][0] == pytest.approx(m * GRAVITY * r / np.deg2rad(SAG_DEG))
    assert character.stiffness_source == {"hinge": "auto"}


def test_names_added_by_eigengait_do_not_clash_and_model_actuators_are_replaced():
    # it has its own 'grid' texture
    character = load_character(MODELS / "suite" / "humanoid_CMU.xml")
    world = build_world(character)
    assert world.model.nu == character.internal_dofs  # eigengait's motors only
    assert world.model.sensor(0).name == "eigengait:com"
    assert "actuator" in character.scene.removed


def test_y_up_model_is_turned_to_stand_on_its_feet():
    character = load_character(MODELS / "locomotion" / "humanoid_CMU_V2020.xml")
    model = build_world(character).model
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert data.xpos[model.body("head").id][2] > data.xpos[model.body("ltoes").id][2] + 1.0
    assert character.scene.added_free_joint


def test_mirror_pairs_from_names():
    assert mirror_pairs(
        ["lfemurrx", "rfemurrx", "lowerback", "left_hip", "right_hip", "knee_l", "knee_r"]
    ) == {
        "lfemurrx": "rfemurrx",
        "left_hip": "right_hip",
        "knee_l": "knee_r",
    }


def test_body_choice_errors_name_the_fix():
    quadruped = MODELS / "suite" / "quadruped.xml"
    with pytest.raises(UserInputError, match="no body 'nose'.*torso, ball"):
        load_character(quadruped, body="nose", stiffness="auto")
    with pytest.raises(UserInputError, match="no internal joints"):
        load_character(quadruped, body="ball", stiffness="auto")
    with pytest.raises(UserInputError, match="stiffness='auto'"):
        load_character(quadruped)


@pytest.mark.parametrize(
    "model",
    [
        "suite/humanoid.xml",
        "suite/quadruped.xml",
        "suite/cheetah.xml",
        "locomotion/humanoid_CMU_V2020.xml",
    ],
)
def test_cli_inspect_and_sketch_new(tmp_path, eigengait_cli, model):
    side = tmp_path / "c.eigengait.yaml"
    r = eigengait_cli(
        "character", "inspect", MODELS / model, "--stiffness", "auto", "--json", "-o", side
    )
    assert r.returncode == 0, r.stderr
    info = json.loads(r.stdout)
    assert info["internal_dofs"] == EXPECTED[model][0] and side.exists()
    r = eigengait_cli("sketch", "new", side, "-o", tmp_path / "s.yaml")
    assert r.returncode == 0, r.stderr
    assert f"character: {side.name}" in (tmp_path / "s.yaml").read_text()


def test_root_layout_of_planar_and_free_roots():
    walker = build_world(load_character(WALKER, stiffness="auto"))
    root = walker.root  # walker.xml: rootz, rootx, rooty (axis +y)
    assert (root.kind, root.height_qpos, root.forward_qpos, root.pitch_qpos, root.pitch_sign) == (
        "planar",
        0,
        1,
        2,
        1.0,
    )
    assert root.translation_qvel == (0, 1)
    qpos = np.zeros(walker.model.nq)
    root.lift_and_pitch(qpos, 0.1, 0.3)
    assert qpos[:3] == pytest.approx([0.1, 0.0, 0.3]) and root.up_z(qpos) == pytest.approx(
        np.cos(0.3)
    )
    free = build_world(load_character("humanoid")).root
    assert (
        free.kind,
        free.translation_qvel,
        free.forward_qvel,
        free.vertical_qvel,
        free.quat_qpos,
    ) == (
        "free",
        (0, 1, 2),
        0,
        2,
        3,
    )
    q = np.array([0, 0, 1.0, 1, 0, 0, 0])
    free.lift_and_pitch(q, 0.1, np.pi)  # upside down about y
    assert q[2] == pytest.approx(1.1) and free.up_z(q) == pytest.approx(-1.0)


def test_a_root_frame_turned_in_the_zero_pose_stands_upright_there():
    """dm_control's CMU humanoid turns its root body 90° about x: standing in its zero pose it is
    upright (up_z 1, no tilt, heading 0), and a pitch is read from that pose as on any model."""
    root = build_world(load_character(MODELS / "suite" / "humanoid_CMU.xml")).root
    w, x, y, z = root.rest_quat
    assert (w, x, y, z) == pytest.approx((np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0))
    qpos = np.zeros(63)
    qpos[3:7] = root.rest_quat
    pitch, roll = root.tilt_deg(qpos)
    assert root.up_z(qpos) == pytest.approx(1.0) and (pitch, roll) == pytest.approx((0.0, 0.0))
    assert root.heading(qpos) == pytest.approx(0.0)
    root.lift_and_pitch(qpos, 0.0, 0.3)  # turned 0.3 rad about world +y
    turn = np.zeros(4)
    mujoco.mju_mulQuat(turn, qpos[3:7], np.array([w, -x, -y, -z]))
    assert root.upright_quat(qpos) == pytest.approx(turn)
    assert root.up_z(qpos) == pytest.approx(np.cos(0.3))
    assert abs(root.tilt_deg(qpos)[0]) == pytest.approx(np.degrees(0.3))


@pytest.mark.parametrize(
    "xml, expected",
    [
        (
            '<mujoco><worldbody><body><geom size=".1"/></body></worldbody></mujoco>',
            "the model has no joints",
        ),
        (
            '<mujoco><worldbody><body><joint type="slide"/><geom size=".1"/><body><joint '
            'name="h"/><geom size=".1"/></body></body></worldbody></mujoco>',
            "field 'the root body (unnamed)'",
        ),
        (
            '<mujoco><worldbody><body><freejoint/><geom size=".1"/><body><joint name="h"/><geom '
            'size=".1"/></body></body></worldbody><sensor><actuatorfrc '
            'actuator="none"/></sensor></mujoco>',
            "cannot compile",
        ),
    ],
)
def test_unusable_models_give_one_clear_error(tmp_path, xml, expected):
    path = tmp_path / "m.xml"
    path.write_text(xml)
    with pytest.raises(UserInputError, match=re.escape(expected)):
        load_character(path, stiffness="auto")
