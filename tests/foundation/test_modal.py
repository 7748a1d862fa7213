"""Modal analysis: reduced vs maximal coordinates, closed forms, simulation, and the built-in
library."""

import mujoco
import numpy as np
import pytest
import yaml

from eigengait.character import builtin_names, load_character
import eigengait.modal.analysis as analysis
from eigengait.modal import ModeSet, compute_modes
from eigengait.modal.eigen import canonical_eigenspaces, constrained_modes, degenerate_blocks
from eigengait.modal.modeset import canonical_signs
from eigengait.modal.maximal import maximal_modes
from eigengait.modal.reduced import mass_matrix
from eigengait.sim import WorldOptions, build_world
from random_tree import random_tree


@pytest.mark.parametrize("seed", range(8))
def test_reduced_and_maximal_formulations_agree_on_random_trees(tmp_path, seed):
    rng = np.random.default_rng(seed)
    character = load_character(random_tree(rng, tmp_path, n_bodies=int(rng.integers(3, 9))))
    world = build_world(character, options=WorldOptions(gravity=False, floor=False))
    for phase, pin in (("air", None), ("ground", "tip_toe")):
        reduced = compute_modes(world, phase)
        lam, joint_shapes, rigid = maximal_modes(world, pin)
        f_max = np.sqrt(lam) / (2 * np.pi)
        assert rigid == reduced.rigid_modes == (6 if phase == "air" else 3)
        np.testing.assert_allclose(f_max, reduced.frequencies_hz, rtol=1e-6)
        # joint-space shapes agree up to sign (distinct frequencies only)
        distinct = np.r_[True, np.diff(reduced.frequencies_hz) > 1e-6 * reduced.frequencies_hz[1:]]
        distinct &= np.r_[
            np.diff(reduced.frequencies_hz) > 1e-6 * reduced.frequencies_hz[:-1], True
        ]
        ours = reduced.shapes[world.internal_qvel][:, distinct]
        theirs = joint_shapes[:, distinct]
        cos = (
            np.abs(np.sum(ours * theirs, 0))
            / np.linalg.norm(ours, axis=0)
            / np.linalg.norm(theirs, axis=0)
        )
        np.testing.assert_allclose(cos, 1.0, atol=1e-6)


def two_boxes(tmp_path, k):
    """Two identical boxes end to end along x, joined by a ball joint at the shared face."""
    xml = """<mujoco><worldbody><body name="a" pos="0 0 1"><freejoint/>
      <geom type="box" size="0.3 0.05 0.1" pos="-0.3 0 0"/>
      <body name="b"><joint name="j" type="ball" stiffness="1"/><geom type="box" size="0.3 0.05 0.1" pos="0.3 0 0"/>
      </body></body></worldbody></mujoco>"""  # noqa: E501
    (tmp_path / "pair.xml").write_text(xml)
    (tmp_path / "pair.eigengait.yaml").write_text(
        yaml.safe_dump(
            {"eigengait": 1, "stiffness": {"j": [float(x) for x in k]}, "damping_ratio": 0.0}
        )
    )
    return load_character(tmp_path / "pair.xml")


def test_two_box_frequencies_match_closed_form(tmp_path):
    # Symmetric free-free pair: each box spins about its own COM, relative angle 2α, so ω² = 2k
    # / I_c.
    k = np.array([30.0, 70.0, 110.0])
    character = two_boxes(tmp_path, k)
    m = 1000 * 0.6 * 0.1 * 0.2
    a, b, c = 0.6, 0.1, 0.2
    inertia = m / 12 * np.array([b**2 + c**2, a**2 + c**2, a**2 + b**2])
    expected = np.sort(np.sqrt(2 * k / inertia) / (2 * np.pi))
    modes = compute_modes(character, "air")
    np.testing.assert_allclose(modes.frequencies_hz, expected, rtol=1e-9)


def test_simulated_oscillation_matches_modal_frequency_with_anisotropic_springs(tmp_path):
    character = two_boxes(tmp_path, [30.0, 70.0, 110.0])
    world = build_world(
        character, options=WorldOptions(gravity=False, floor=False, timestep=0.0005)
    )
    assert world.model.nu == 6  # 3 motors + 3 anisotropic spring actuators
    modes = compute_modes(world, "air")
    M = mass_matrix(world)
    for i in range(modes.count):
        data = world.new_data()
        mujoco.mj_integratePos(world.model, data.qpos, modes.shapes[:, i] * 0.02, 1.0)
        period = 1 / modes.frequencies_hz[i]
        n = int(3 * period / world.model.opt.timestep)
        coord = np.empty(n)
        dq = np.zeros(world.model.nv)
        for s in range(n):
            mujoco.mj_step(world.model, data)
            mujoco.mj_differentiatePos(world.model, dq, 1.0, world.model.qpos0, data.qpos)
            coord[s] = modes.shapes[:, i] @ M @ dq
        crossings = np.flatnonzero(np.diff(np.sign(coord)) > 0) * world.model.opt.timestep
        measured = np.mean(np.diff(crossings))
        assert abs(measured / period - 1) < 0.01


@pytest.mark.parametrize("name", builtin_names())
def test_builtin_characters_have_modes_in_both_phases(name):
    character = load_character(name)
    world = build_world(character, options=WorldOptions(gravity=False))
    air = compute_modes(world, "air")
    ground = compute_modes(world, "ground")
    # slide x, slide z, hinge y: 3 rigid modes in the air, 1 on a pinned toe
    planar = bool(character.root_joints)
    assert (air.rigid_modes, ground.rigid_modes) == ((3, 1) if planar else (6, 3))
    assert air.count == ground.count == character.internal_dofs
    # gait-scale lowest modes; the planar walker pinned at the toe of its 0.2 m foot: 0.50 Hz
    assert 0.4 <= air.frequencies_hz[0] <= 5.0 and 0.4 <= ground.frequencies_hz[0] <= 5.0
    M = mass_matrix(world)
    np.testing.assert_allclose(air.shapes.T @ M @ air.shapes, np.eye(air.count), atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(air.torque_basis, axis=0), 1.0)


def test_library_matches_the_thesis_sizes():
    dofs = {n: load_character(n).internal_dofs for n in ("humanoid", "monster", "kangaroo")}
    assert dofs == {"humanoid": 30, "monster": 42, "kangaroo": 36}
    humanoid = build_world(load_character("humanoid"))
    assert humanoid.model.nbody - 1 == 11 and 50 < humanoid.mass() < 90


def test_relax_pose_moves_the_spring_rest_and_the_modes():
    character = load_character("humanoid")
    default = build_world(character, options=WorldOptions(gravity=False))
    crouched = build_world(character, "crouched", WorldOptions(gravity=False))
    d0, d1 = default.new_data(), crouched.new_data()
    pelvis = default.root_body
    assert d1.xpos[pelvis][2] < d0.xpos[pelvis][2] - 0.05  # the hips are lower when crouched
    for _ in range(400):  # springs rest at the new pose: nothing moves
        mujoco.mj_step(crouched.model, d1)
    assert np.abs(d1.qvel).max() < 1e-6
    f0 = compute_modes(default, "ground").frequencies_hz
    f1 = compute_modes(crouched, "ground").frequencies_hz
    assert np.abs(f1 / f0 - 1).max() > 0.01


def test_modeset_round_trip(tmp_path):
    modes = compute_modes(load_character("kangaroo"), "ground")
    modes.save(tmp_path / "k.npz")
    back = ModeSet.load(tmp_path / "k.npz")
    assert back.summary() == modes.summary()
    np.testing.assert_array_equal(back.shapes, modes.shapes)
    np.testing.assert_array_equal(back.torque_basis, modes.torque_basis)


def _rounded_differently(seed: int, share: float = 1e-15):
    """`constrained_modes` on K and M whose every entry is off by `share` of itself (symmetric):
    what another CPU's linear algebra may hand the solver."""

    def solve(K, M, G=None):
        rng = np.random.default_rng(seed)
        dK, dM = (rng.standard_normal(A.shape) * share * abs(A) for A in (K, M))
        return constrained_modes(K + (dK + dK.T) / 2, M + (dM + dM.T) / 2, G)

    return solve


@pytest.mark.parametrize("name", ["dog", "humanoid", "monster"])
def test_mode_bases_do_not_depend_on_rounding(name, monkeypatch):
    """The dog's twin legs make exactly repeated frequencies (front and rear pairs) and every
    symmetric character ties left and right entries: the raw solver's vectors there turn and flip
    with the last bits of K and M, so a gait's ψ would mean other torques on another machine."""
    character = load_character(name)
    phases = [("air", None)] + [("ground", foot) for foot in character.feet]
    exact = [compute_modes(character, phase, foot) for phase, foot in phases]
    if name == "dog":
        assert degenerate_blocks(exact[0].frequencies_hz ** 2)  # the case under test is there
    for seed in range(2):
        monkeypatch.setattr(analysis, "constrained_modes", _rounded_differently(seed, 1e-13))
        for (phase, foot), reference in zip(phases, exact):
            again = compute_modes(character, phase, foot)
            np.testing.assert_allclose(again.torque_basis, reference.torque_basis, atol=1e-6)
            np.testing.assert_allclose(again.shapes, reference.shapes, atol=1e-6)


def test_a_repeated_eigenvalue_gets_one_basis_whatever_the_solver_returned():
    """K = diag(1, 4, 4, 9), M = I: modes 2 and 3 share λ = 4, and any rotation of e2, e3 solves
    the problem; two different rotations canonicalize to the same orthonormal basis."""
    lam = np.array([1.0, 4.0, 4.0, 9.0])
    assert degenerate_blocks(lam) == [slice(1, 3)]
    eye = np.eye(4)
    canonical = []
    for angle in (0.3, 2.1):
        c, s = np.cos(angle), np.sin(angle)
        shapes = eye.copy()
        shapes[:, 1:3] = eye[:, 1:3] @ np.array([[c, -s], [s, c]])
        canonical.append(canonical_eigenspaces(lam, shapes))
    first, second = (X * canonical_signs(X) for X in canonical)
    np.testing.assert_allclose(first, second, atol=1e-12)
    np.testing.assert_allclose(first.T @ first, eye, atol=1e-12)
    # the block's basis diagonalizes the coordinate weights: the unit vectors themselves
    np.testing.assert_allclose(first, eye, atol=1e-12)


def test_sign_convention_breaks_a_left_right_tie_by_dof_order():
    """Equal magnitudes on a left and a right joint, one of them larger by rounding: the first
    entry decides the sign either way; a clear largest entry decides it as before."""
    tied = np.array([[0.5], [-0.5 - 1e-13], [0.1]])
    other = np.array([[0.5 + 1e-13], [-0.5], [0.1]])
    assert canonical_signs(tied)[0] == canonical_signs(other)[0] == 1.0
    clear = np.array([[0.2], [-0.9], [0.1]])
    assert canonical_signs(clear)[0] == -1.0
