"""Sketch presets against the thesis's Table 5.1 search-space sizes, and the seeded random sketches
of §5.3.4."""

import pytest
import yaml

from eigengait.character import load_character
from eigengait.control.binding import bind_sketch
from eigengait.control.library import resolve
from eigengait.control.random_sketch import DRAW_FROM, PROCEDURES, random_sketch
from eigengait.control.sketch import Sketch, load_sketch

# Table 5.1: (priority air / ground, optimized air / ground)
TABLE_5_1 = {
    "basic-run": ((3, 4), (5, 7)),
    "lateral-sway": ((3, 3), (5, 6)),
    "vertical-rotation": ((3, 4), (5, 7)),
    "skipping": ((3, 8), (5, 10)),
    "crouched": ((3, 5), (5, 8)),
    "legs-apart": ((3, 4), (5, 7)),
    "one-foot-hop": ((2, 5), (6, 8)),
    "monster": ((3, 4), (5, 7)),
    "kangaroo": ((1, 3), (4, 6)),
    "trivial-selection": ((3, 4), (12, 12)),
    "random-1": ((3, 4), (8, 8)),
    "random-2": ((2, 3), (6, 7)),
}


@pytest.mark.parametrize("name", TABLE_5_1)
def test_preset_search_space_matches_table_5_1(name):
    sketch = load_sketch(resolve("sketch", name))
    priority, optimized = TABLE_5_1[name]
    assert (len(sketch.air.priority), len(sketch.ground.priority)) == priority
    assert (
        len(sketch.air.optimized_modes(1000)),
        len(sketch.ground.optimized_modes(1000)),
    ) == optimized


@pytest.mark.parametrize("procedure", [1, 2])
def test_random_sketches_follow_the_procedure_and_the_seed(procedure):
    humanoid = load_character("humanoid")
    drawn = random_sketch(humanoid, "humanoid", seed=7, procedure=procedure)
    air_n, ground_n, amplitude, air_total, ground_total = PROCEDURES[procedure]
    sketch = Sketch.model_validate(yaml.safe_load(yaml.safe_dump(drawn)))
    bind_sketch(sketch)  # every mode it names exists
    assert (len(sketch.air.priority), len(sketch.ground.priority)) == (air_n, ground_n)
    assert (len(sketch.air.optimized_modes(1000)), len(sketch.ground.optimized_modes(1000))) == (
        air_total,
        ground_total,
    )
    for phase in (sketch.air, sketch.ground):
        assert max(phase.priority) <= DRAW_FROM
        assert len({abs(v) for v in phase.priority.values()}) == 1  # one amplitude, random signs
    assert random_sketch(humanoid, "humanoid", seed=7, procedure=procedure) == drawn
    assert random_sketch(humanoid, "humanoid", seed=8, procedure=procedure) != drawn


@pytest.mark.parametrize("name, seed, procedure", [("random-1", 1, 1), ("random-2", 2, 2)])
def test_the_random_presets_are_the_documented_draws(name, seed, procedure):
    """`sketch new humanoid --random SEED --procedure P` regenerates the shipped random presets
    exactly."""
    drawn = random_sketch(load_character("humanoid"), "humanoid", seed=seed, procedure=procedure)
    assert yaml.safe_load(resolve("sketch", name).read_text()) == yaml.safe_load(
        yaml.safe_dump(drawn)
    )
