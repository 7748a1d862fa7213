"""Random articulated trees (boxes, ball and hinge joints, anisotropic stiffness) written as MJCF +
sidecar."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import yaml


def random_tree(
    rng: np.random.Generator,
    folder: Path,
    n_bodies: int = 6,
    hinge_fraction: float = 0.3,
    anisotropic: bool = True,
    name: str = "tree",
) -> Path:
    """Write `name.xml` (+ sidecar) with a free root and n_bodies-1 random joints; returns the MJCF
    path."""
    lines = [f'<mujoco model="{name}"><worldbody>']
    stiffness = {}
    parents = [-1]
    for i in range(1, n_bodies):
        parents.append(int(rng.integers(0, i)))
    children = {i: [c for c in range(n_bodies) if parents[c] == i] for i in range(n_bodies)}

    def body(i: int, depth: int) -> None:
        half = rng.uniform(0.03, 0.2, 3)
        pos = [0, 0, 1] if i == 0 else rng.uniform(-0.3, 0.3, 3)
        quat = rng.normal(size=4)
        quat /= np.linalg.norm(quat)
        lines.append(
            f'<body name="b{i}" pos="{" ".join(map(str, pos))}" quat="{" ".join(map(str, quat))}">'
        )
        if i == 0:
            lines.append('<freejoint name="root"/>')
        elif rng.random() < hinge_fraction:
            axis = rng.normal(size=3)
            lines.append(
                f'<joint name="j{i}" type="hinge" axis="{" ".join(map(str, axis))}" '
                f'pos="{" ".join(map(str, rng.uniform(-0.1, 0.1, 3)))}" '
                f'stiffness="{rng.uniform(5, 50)}"/>'
            )
        else:
            k = rng.uniform(5, 50)
            lines.append(
                f'<joint name="j{i}" type="ball" '
                f'pos="{" ".join(map(str, rng.uniform(-0.1, 0.1, 3)))}" stiffness="{k}"/>'
            )
            if anisotropic:
                stiffness[f"j{i}"] = [float(x) for x in rng.uniform(5, 50, 3)]
        lines.append(
            f'<geom type="box" size="{" ".join(map(str, half))}" '
            f'pos="{" ".join(map(str, rng.uniform(-0.1, 0.1, 3)))}" '
            f'density="{rng.uniform(300, 2000)}"/>'
        )
        if i == n_bodies - 1:
            lines.append(
                f'<site name="tip_toe" pos="{" ".join(map(str, rng.uniform(-0.1, 0.1, 3)))}"/>'
            )
        for c in children[i]:
            body(c, depth + 1)
        lines.append("</body>")

    body(0, 0)
    lines.append("</worldbody></mujoco>")
    path = folder / f"{name}.xml"
    path.write_text("\n".join(lines))
    if stiffness:
        (folder / f"{name}.eigengait.yaml").write_text(
            yaml.safe_dump({"eigengait": 1, "stiffness": stiffness})
        )
    return path
