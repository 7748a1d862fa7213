"""Where the tests find the shared real data: `shared/` beside the repository (mocap clips and
dm_control models; each folder's README gives units and terms of use)."""

from pathlib import Path

SHARED_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
MOCAP = SHARED_DATA / "mocap"
DM_CONTROL = SHARED_DATA / "models" / "dm_control"


def clip_start(clip: Path, frames: int, out: Path) -> Path:
    """Write the first `frames` frames of the BVH `clip` (120 frames/s) to `out`; returns `out`."""
    lines = clip.read_text().splitlines()
    header = lines.index("MOTION")
    kept = [f"Frames: {frames}", "Frame Time: .0083333"] + lines[header + 3 : header + 3 + frames]
    out.write_text("\n".join(lines[: header + 1] + kept) + "\n")
    return out
