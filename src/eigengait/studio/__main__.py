"""`python -m eigengait.studio [CHARACTER | SKETCH] [--host H] [--port N]`: the studio without the main CLI."""

import argparse
import sys

from eigengait.errors import UserInputError
from eigengait.studio.app import main

parser = argparse.ArgumentParser(prog="python -m eigengait.studio", description=__doc__)
parser.add_argument("target", nargs="?", help="built-in character, MJCF file, shipped sketch or sketch file")
parser.add_argument("--host", default="127.0.0.1")
parser.add_argument("--port", type=int, default=8080)
args = parser.parse_args()
try:
    main(args.target, args.host, args.port)
except UserInputError as err:
    print(f"error: {err}", file=sys.stderr)
    sys.exit(2)
