import os
import sys

import pytest

os.environ.setdefault("MUJOCO_GL", "egl")


@pytest.fixture
def eigengait_cli():
    """Run the installed `eigengait` command as a user would; returns CompletedProcess."""
    import subprocess

    def run(*args, cwd=None, timeout=600):
        return subprocess.run(
            [sys.executable, "-m", "eigengait", *map(str, args)],
            capture_output=True,
            text=True,
            cwd=cwd,
            timeout=timeout,
        )

    return run
