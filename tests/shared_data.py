"""Where the tests find the shared real data: `shared/` beside the repository (mocap clips and
dm_control models; each folder's README gives units and terms of use)."""

from pathlib import Path

SHARED_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
MOCAP = SHARED_DATA / "mocap"
DM_CONTROL = SHARED_DATA / "models" / "dm_control"
