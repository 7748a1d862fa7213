"""Controller and sketch files of format 1 (modes numbered in the eigensolver's own vectors) play
and ask for the torques they did before the canonical mode bases."""

import json

import numpy as np
import yaml

from eigengait.character import load_character
from eigengait.control.binding import gait_system
from eigengait.control.controller import FORMAT_VERSION, load_controller, to_parameters
from eigengait.control.legacy_modes import LEGACY_FORMAT, mode_transforms
from eigengait.control.library import resolve
from eigengait.control.sketch import load_sketch
from eigengait.modal.analysis import compute_modes, solver_torque_basis
from eigengait.sim import WorldOptions, build_world


def _as_format_1(tmp_path, name: str):
    """The shipped gait's file with its numbers read as format 1."""
    data = json.loads(resolve("gait", name).read_text())
    assert data["eigengait_controller"] == FORMAT_VERSION
    data["eigengait_controller"] = LEGACY_FORMAT
    path = tmp_path / f"{name}-format-1.json"
    path.write_text(json.dumps(data))
    return load_controller(path)


def test_a_format_1_file_plays_the_torques_of_its_solver_vectors(tmp_path):
    """The dog: its air modes 6 and 7 share a frequency (the canonical basis turns them) and some
    ground modes change sign. Per state, the torques of the activations and of each event gain
    column, read in the canonical bases, are those of the file's numbers in the solver's vectors."""
    controller = _as_format_1(tmp_path, "dog-trot")
    system = gait_system(controller)
    params = to_parameters(controller, system)
    world = build_world(system.character, system.pose, WorldOptions(gravity=False, floor=False))
    foot = system.active_feet[0]
    legacy = {phase: solver_torque_basis(world, phase, foot) for phase in ("air", "ground")}
    for phase in ("air", "ground"):
        canonical = system.basis_matrix(foot, phase)
        psi = np.zeros(canonical.shape[1])
        for mode, value in controller.activations[foot][phase].items():
            psi[mode - 1] = value
        np.testing.assert_allclose(
            canonical @ params.activations[(foot, phase)], legacy[phase] @ psi, atol=1e-9
        )
        modes, K = params.feedback.event.phases[phase]
        old_rows = getattr(controller.feedback.event, phase)
        old_modes = sorted(old_rows)
        old_K = np.array([old_rows[m] for m in old_modes])
        np.testing.assert_allclose(
            canonical[:, np.asarray(modes) - 1] @ K,
            legacy[phase][:, np.asarray(old_modes) - 1] @ old_K,
            atol=1e-9,
        )
    # the change of basis is a rotation within the repeated pair and sign flips elsewhere
    T = mode_transforms(system.character, system.pose, [foot], {})[("air", foot)]
    np.testing.assert_allclose(T @ T.T, np.eye(len(T)), atol=1e-9)


def test_a_format_2_file_is_read_as_it_is():
    controller = load_controller(resolve("gait", "kangaroo-hop"))
    system = gait_system(controller)
    params = to_parameters(controller, system)
    for foot, phases in controller.activations.items():
        for phase, rows in phases.items():
            for mode, value in rows.items():
                assert params.activations[(foot, phase)][mode - 1] == value


def _dense(priority: dict[int, float], count: int) -> np.ndarray:
    psi = np.zeros(count)
    for mode, value in priority.items():
        psi[mode - 1] = value
    return psi


def test_a_format_1_sketch_asks_for_the_torques_it_asked_for(tmp_path):
    """The crouched preset read as format 1: its priority activations, in the canonical bases,
    push the joints as its numbers did in the solver's own vectors, per phase."""
    text = resolve("sketch", "crouched").read_text()
    assert "eigengait_sketch: 2" in text
    path = tmp_path / "crouched-format-1.yaml"
    path.write_text(text.replace("eigengait_sketch: 2", "eigengait_sketch: 1"))
    as_written = yaml.safe_load(path.read_text())
    sketch = load_sketch(path)
    assert sketch.eigengait_sketch == 2
    world = build_world(
        load_character("humanoid"), "crouched", WorldOptions(gravity=False, floor=False)
    )
    for phase in ("air", "ground"):
        foot = "left" if phase == "ground" else None
        canonical = compute_modes(world, phase, foot).torque_basis
        legacy = solver_torque_basis(world, phase, foot)
        count = canonical.shape[1]
        np.testing.assert_allclose(
            canonical @ _dense(sketch.phase(phase).priority, count),
            legacy @ _dense(as_written[phase]["priority"], count),
            atol=1e-9,
        )
