"""The MuJoCo world: a character at its relax pose with passive springs, ground contact and joint
motors."""

from eigengait.sim.world import World, WorldOptions, build_world

__all__ = ["World", "WorldOptions", "build_world"]
