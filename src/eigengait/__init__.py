"""eigengait: physics-based character animation from natural vibration modes."""

import os

# Offscreen rendering without a display: MuJoCo reads MUJOCO_GL when it creates a GL context.
os.environ.setdefault("MUJOCO_GL", "egl")
os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])

__version__ = "0.1.0"
