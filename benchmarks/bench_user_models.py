"""Users' MJCF models (shared/data/models/dm_control): load time, DOF, lowest modes and `modes` time
per model.

`load` is `load_character(..., stiffness="auto")`; `modes` is `compute_modes` in the air phase on
the loaded character (world build + mass matrix + eigenproblem), best of 3. Prints a Markdown table.
Run: .venv/bin/python benchmarks/bench_user_models.py
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

from eigengait.character import load_character
from eigengait.modal import compute_modes

MODELS = Path(__file__).resolve().parents[2] / "shared" / "data" / "models" / "dm_control"
FILES = [
    "suite/humanoid.xml",
    "suite/humanoid_CMU.xml",
    "suite/quadruped.xml",
    "suite/walker.xml",
    "suite/cheetah.xml",
    "locomotion/humanoid_CMU_V2020.xml",
]


def best_of(n: int, job) -> tuple[float, object]:
    times, out = [], None
    for _ in range(n):
        start = time.perf_counter()
        out = job()
        times.append(time.perf_counter() - start)
    return min(times), out


def main() -> None:
    warnings.simplefilter("ignore")
    print(
        "| model | root | internal DOF | feet | air modes 1–3 (Hz) | ground modes 1–3 (Hz) | "
        "load (s) | modes (s) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for name in FILES:
        t_load, character = best_of(1, lambda: load_character(MODELS / name, stiffness="auto"))
        t_modes, air = best_of(3, lambda: compute_modes(character))
        ground = compute_modes(character, "ground")
        root = (
            "planar"
            if character.root_joints
            else ("free (added)" if character.scene.added_free_joint else "free")
        )
        print(
            f"| `{name}` | {root} | {character.internal_dofs} | {len(character.feet)} | "
            f"{', '.join(f'{f:.2f}' for f in air.frequencies_hz[:3])} | "
            f"{', '.join(f'{f:.2f}' for f in ground.frequencies_hz[:3])} | {t_load:.2f} | "
            f"{t_modes:.2f} |"
        )


if __name__ == "__main__":
    main()
