"""Track a motion-capture clip in physics with the balance controller and print how well it held.

    python examples/track_a_clip.py [CLIP.bvh] [--robustness R]

Default clip: the CMU 02_01 walk from the shared data (CMU's terms of use in its README).
"""

import argparse
from pathlib import Path

from eigengait.motion.tracking import run_track

WALK = Path(__file__).resolve().parents[2] / "shared/data/mocap/cmu_02_01_walk.bvh"

parser = argparse.ArgumentParser()
parser.add_argument("clip", nargs="?", default=str(WALK))
parser.add_argument("--robustness", type=float, default=0.5)
args = parser.parse_args()

world, reference, result = run_track(
    Path(args.clip),
    "walker",
    args.robustness,
    push=None,
    mapping=None,
    start_frame=1,
    tolerance=0.0,
)
print(f"tracked {result.duration_s:.2f} of {reference.duration:.2f} s, fell: {result.fell}")
print(
    f"joint RMS {result.joint_rms_deg:.1f} deg, COM error {result.com_error_m:.3f} m, "
    f"mean artificial torque {result.artificial_torque:.1f} N·m"
)
