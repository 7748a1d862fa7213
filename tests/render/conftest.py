import pytest


@pytest.fixture(scope="session")
def humanoid():
    """The humanoid's world (default relax pose, no gravity) and its air-phase modes."""
    from eigengait.character import load_character
    from eigengait.modal import compute_modes
    from eigengait.sim.world import WorldOptions, build_world

    world = build_world(load_character("humanoid"), "default", WorldOptions(gravity=False))
    return world, compute_modes(world, "air")
