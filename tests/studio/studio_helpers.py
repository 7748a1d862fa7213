"""Shared by the studio tests: GUI labels, artifact folders."""

import shutil
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
ARTIFACTS = REPO / "test-artifacts" / "studio"
DOC_IMAGES = REPO / "docs" / "images"


def gui_label(studio, phase: str, mode: int) -> str:
    return f"{phase} {mode} · {studio.state.modes(phase).frequencies_hz[mode - 1]:.2f} Hz"


def save_doc_image(source: Path, name: str) -> None:
    DOC_IMAGES.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(source, DOC_IMAGES / name)
