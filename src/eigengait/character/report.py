"""What `eigengait character inspect` shows about a loaded character, and the editable sidecar it
writes."""

from __future__ import annotations

import os
from pathlib import Path

import yaml

from eigengait.character.guess import mirror_pairs
from eigengait.character.loader import Character
from eigengait.character.metadata import FORMAT_VERSION


def describe(character: Character) -> dict:
    """A JSON-ready description: root, joints (kind, stiffness and its source), feet, mirror pairs,
    notes."""
    scene = character.scene
    pairs = character.meta.mirror.pairs if character.meta.mirror else mirror_pairs(character.joints)
    return {
        "character": character.name,
        "model": str(character.path),
        "sidecar": str(character.sidecar) if character.sidecar else None,
        "root": {
            "body": scene.root,
            "kind": "planar" if scene.root_joints else "free",
            "joints": scene.root_joints,
            "free_joint_added": scene.added_free_joint,
        },
        "internal_dofs": character.internal_dofs,
        "joints": [
            {
                "name": j,
                "kind": "ball" if character.joint_dofs[j] == 3 else "hinge",
                "stiffness": [round(float(k), 6) for k in character.stiffness[j]],
                "stiffness_source": character.stiffness_source[j],
            }
            for j in character.joints
        ],
        "feet": {
            name: {
                "toe": f.toe,
                "heel": f.heel,
                "guessed": any(g.site == f.toe for g in character.guessed_feet),
            }
            for name, f in character.feet.items()
        },
        "gait_order": character.meta.gait_order,
        "mirror_pairs": pairs,
        "removed_from_model": scene.removed,
        "notes": scene.notes,
    }


def sidecar_yaml(character: Character, output: Path) -> str:
    """A standalone sidecar (with `model:` relative to `output`) that reloads the character as
    inspected."""
    meta = character.meta
    data = {
        "eigengait": FORMAT_VERSION,
        "model": os.path.relpath(character.path.resolve(), output.resolve().parent),
        "body": character.scene.root,
        "feet": {
            name: {k: v for k, v in f.model_dump().items() if v is not None}
            for name, f in meta.feet.items()
        },
        "gait_order": list(meta.gait_order),
    }
    pairs = meta.mirror.pairs if meta.mirror else mirror_pairs(character.joints)
    if pairs:
        data["mirror"] = {"axis": meta.mirror.axis if meta.mirror else "y", "pairs": dict(pairs)}
    chosen = {
        j: _stiffness_value(character, j)
        for j in character.joints
        if character.stiffness_source[j] in ("auto", "sidecar")
    }
    if chosen:
        data["stiffness"] = chosen
    data["damping_ratio"] = meta.damping_ratio
    if meta.strength is not None:
        data["strength"] = meta.strength
    if meta.relax_poses:
        data["relax_poses"] = {
            p: {j: list(v) if isinstance(v, tuple) else v for j, v in rot.items()}
            for p, rot in meta.relax_poses.items()
        }
    header = (
        f"# eigengait character sidecar for {character.path.name}: edit and pass this file as "
        "CHARACTER.\n"
        "# stiffness lists the joints whose stiffness is not in the MJCF (N·m/rad; ball: kx, ky, "
        "kz).\n"
    )
    return header + yaml.safe_dump(data, sort_keys=False, allow_unicode=True)


def _stiffness_value(character: Character, joint: str):
    k = [round(float(v), 4) for v in character.stiffness[joint]]
    return k[0] if len(k) == 1 else k
