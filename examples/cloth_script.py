"""Run a FLEX3D cloth script from Python and print how far its springs stretch.

python examples/cloth_script.py [SCRIPT.PAR or example name] [--seconds S]
"""

import argparse

from eigengait.cloth.library import resolve_script
from eigengait.cloth.model import script_model
from eigengait.cloth.par import read_par
from eigengait.cloth.simulate import run_frames
from eigengait.cloth.strain import max_strain

parser = argparse.ArgumentParser()
parser.add_argument("script", nargs="?", default="curtain")
parser.add_argument("--seconds", type=float, default=2.0)
args = parser.parse_args()

script = read_par(resolve_script(args.script))
model = script_model(script)
for frame in run_frames(
    model,
    time_step=script.time_step,
    duration=args.seconds,
    frames_per_second=script.frames_per_second,
    strain_limit=0.1,
):
    strain = max_strain(frame.positions, model.springs, model.spring_rest)
    print(
        f"t = {frame.time:5.2f} s: lowest point z = {frame.positions[:, 2].min():7.3f} m, "
        f"largest spring strain {100 * strain:5.1f} %"
    )
