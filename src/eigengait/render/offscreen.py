"""The offscreen GL context's backend: the one place eigengait touches MuJoCo's GL environment
variables.

MuJoCo picks the GL backend for `mujoco.Renderer` from MUJOCO_GL (and PyOpenGL its platform from
PYOPENGL_PLATFORM) when `mujoco` is first imported. Without a display only EGL (or OSMesa) works, so
before the first GL context eigengait asks for EGL, unless the user chose a backend by setting
MUJOCO_GL themselves. Importing eigengait sets nothing.
"""

from __future__ import annotations

import importlib
import os
import sys

DEFAULT_BACKEND = "egl"


def use_offscreen_gl() -> None:
    """Choose MuJoCo's GL backend for offscreen rendering: MUJOCO_GL as the user set it, else EGL
    (and PYOPENGL_PLATFORM likewise). Call before creating a `mujoco.Renderer`.

    `mujoco` may already have been imported with MUJOCO_GL unset, which picks an on-screen backend
    (GLFW); its GL context module is then read again so the renderer gets the backend now named. No
    GL context exists before the first renderer, so nothing that was already created changes.
    """
    os.environ.setdefault("MUJOCO_GL", DEFAULT_BACKEND)
    os.environ.setdefault("PYOPENGL_PLATFORM", os.environ["MUJOCO_GL"])
    import mujoco

    chosen = getattr(sys.modules.get(mujoco.Renderer.__module__), "gl_context", None)
    wanted = os.environ["MUJOCO_GL"].lower().strip()
    if chosen is not None and getattr(chosen, "_MUJOCO_GL", wanted) != wanted:
        importlib.reload(chosen)


__all__ = ["use_offscreen_gl"]
