"""`python -m eigengait.studio [CHARACTER | SKETCH] [--host H] [--port N]`: the same as `eigengait studio`."""

import sys

from eigengait.cli import main

sys.argv[1:1] = ["studio"]
main()
