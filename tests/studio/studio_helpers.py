"""Shared by the studio tests: GUI labels, artifact folders."""

import os
import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts" / "studio"
DOC_IMAGES = REPO / "docs" / "images"


def gui_label(studio, phase: str, mode: int) -> str:
    return f"{phase} {mode} · {studio.state.modes(phase).frequencies_hz[mode - 1]:.2f} Hz"


def save_doc_image(source: Path, name: str) -> None:
    """Copy a screenshot into docs/images, only when EIGENGAIT_DOC_IMAGES=1 asks for it (a plain
    test run leaves the documentation as committed)."""
    if os.environ.get("EIGENGAIT_DOC_IMAGES") != "1":
        return
    DOC_IMAGES.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(source, DOC_IMAGES / name)
