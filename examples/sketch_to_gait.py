"""From a shipped sketch to a simulated, optimized gait, then play it with physics only.

    python examples/sketch_to_gait.py [PRESET] [--evaluations N] [--output RUN_FOLDER]

A real gait needs thousands of evaluations (README, "Shipped gaits"); the default budget only shows
the calls.
"""

import argparse
import tempfile
from pathlib import Path

from eigengait.control.binding import gait_system
from eigengait.control.controller import load_controller, to_parameters
from eigengait.control.library import resolve
from eigengait.control.playback import play
from eigengait.control.sketch import load_sketch
from eigengait.optimize.mom import MomSettings
from eigengait.optimize.staged import optimize_gait

parser = argparse.ArgumentParser()
parser.add_argument("preset", nargs="?", default="kangaroo")
parser.add_argument("--evaluations", type=int, default=60)
parser.add_argument("--output", type=Path, default=None)
args = parser.parse_args()

folder = args.output or Path(tempfile.mkdtemp(prefix="eigengait-")) / "run"
sketch = load_sketch(resolve("sketch", args.preset))
state = optimize_gait(sketch, folder, MomSettings(max_evaluations=args.evaluations), progress=False)
print(
    f"{state.evaluations} evaluations, best cost {state.best.cost:.4g}, cycle violation "
    f"{state.best.violation:.3g}"
)

controller = load_controller(folder / "best_controller.json")
system = gait_system(controller)
result = play(system, to_parameters(controller, system), cycles=2)
print(
    f"played {result.cycles_completed} of 2 cycles, fell: {result.fell}, speed "
    f"{result.mean_speed_mps:.2f} m/s"
)
print(f"run folder: {folder}")
