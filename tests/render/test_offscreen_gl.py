"""Importing eigengait leaves the environment alone; the renderer chooses the offscreen GL backend
itself."""

import json
import os
import subprocess
import sys

IMPORT_ONLY = """
import json, os
before = dict(os.environ)
import eigengait, eigengait.cli, eigengait.sim, eigengait.render
print(json.dumps({"changed": sorted(k for k in set(before) | set(os.environ) if before.get(k) != os.environ.get(k))}))
"""  # noqa: E501

RENDER_AFTER_MUJOCO = """
import json, os
import numpy as np
from eigengait.character import load_character
from eigengait.sim.world import WorldOptions, build_world  # imports mujoco while MUJOCO_GL is unset
from eigengait.render import FrameRenderer

world = build_world(load_character("humanoid"), "default", WorldOptions(gravity=False))
with FrameRenderer(world, 64, 48) as frames:
    image = frames.render(world.model.qpos0)
print(json.dumps({"backend": os.environ.get("MUJOCO_GL"), "shape": list(image.shape), "spread": int(np.ptp(image))}))
"""  # noqa: E501


def _run(code: str) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("MUJOCO_GL", "PYOPENGL_PLATFORM")}
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_importing_eigengait_sets_no_environment_variable():
    assert _run(IMPORT_ONLY)["changed"] == []


def test_rendering_picks_egl_even_when_mujoco_was_imported_first():
    out = _run(RENDER_AFTER_MUJOCO)
    assert out["backend"] == "egl" and out["shape"] == [48, 64, 3] and out["spread"] > 0
