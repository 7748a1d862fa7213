"""eigengait: physics-based character animation from natural vibration modes.

Importing it has no side effects: offscreen rendering chooses MuJoCo's GL backend itself
(`render.offscreen`).
"""

__version__ = "0.1.0"
