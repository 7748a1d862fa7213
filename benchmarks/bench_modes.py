"""Wall-clock of `eigengait modes CHARACTER --json` (the whole command, start-up included) per
character, against the same process's `python -c pass` start-up as the baseline."""

from __future__ import annotations

import subprocess
import sys
import time

from eigengait.character import builtin_names


def timed(args: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(args, check=True, capture_output=True)
    return time.perf_counter() - start


def main() -> None:
    python = timed([sys.executable, "-c", "pass"])
    print(f"python start-up: {python:.2f} s (baseline)")
    for name in builtin_names():
        for phase in ("air", "ground"):
            t = min(
                timed(
                    [sys.executable, "-m", "eigengait", "modes", name, "--phase", phase, "--json"]
                )
                for _ in range(3)
            )
            print(
                f"eigengait modes {name:9s} --phase {phase:6s} --json: {t:.2f} s  "
                f"({t / python:.1f}× start-up)"
            )


if __name__ == "__main__":
    main()
