"""Load an MJCF model you already have and print its natural vibration modes.

    python examples/modes_of_your_model.py [MODEL.xml] [--count N]

Default model: dm_control's planar walker (no joint stiffness of its own, so it is chosen by
`--stiffness auto`'s rule: each joint sags by a set angle under the weight it carries at the relax
pose).
"""

import argparse
from pathlib import Path

from eigengait.character import load_character
from eigengait.modal import compute_modes

WALKER = Path(__file__).resolve().parents[2] / "shared/data/models/dm_control/suite/walker.xml"

parser = argparse.ArgumentParser()
parser.add_argument("model", nargs="?", default=str(WALKER))
parser.add_argument("--count", type=int, default=6)
args = parser.parse_args()

character = load_character(args.model, stiffness="auto")
for note in character.scene.notes:
    print("note:", note)
modes = compute_modes(character, "air")
print(f"{modes.character}: {modes.dofs} internal DOF, {modes.rigid_modes} rigid-body modes dropped")
for i, f in enumerate(modes.frequencies_hz[: args.count], start=1):
    print(f"mode {i:2d}: {f:8.3f} Hz")
