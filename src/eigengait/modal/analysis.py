"""Air- and ground-phase modes of a character about its relax pose (reduced coordinates)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from eigengait.character.loader import Character
from eigengait.character.relax import DEFAULT_POSE
from eigengait.errors import UserInputError
from eigengait.modal.eigen import canonical_eigenspaces, constrained_modes, frequencies_hz
from eigengait.modal.modeset import ModeSet, canonical_signs, unit_torque_basis
from eigengait.modal.reduced import mass_matrix, point_jacobian, stiffness_matrix
from eigengait.sim.world import World, WorldOptions, build_world

PHASES = ("air", "ground")


def stance_foot(character: Character, foot: str | None) -> str:
    """The foot pinned in the ground phase: the given one, else the first of the gait order."""
    if not character.feet:
        raise UserInputError(
            "the character has no feet, so it has no ground phase",
            file=character.path,
            field="feet",
            fix="add <foot>_toe sites or a feet: entry in the sidecar, or use phase='air'",
        )
    foot = foot or character.meta.gait_order[0]
    if foot not in character.feet:
        raise UserInputError(
            f"unknown foot '{foot}'",
            file=character.path,
            field="feet",
            fix=f"use one of: {', '.join(character.feet)}",
        )
    return foot


def partner_foot(
    character: Character,
    foot: str,
    partner: str,
    file: str | Path | None = None,
    field: str = "partners",
) -> str:
    """A foot pinned with stance foot `foot`: one of the character's feet, not `foot` itself. An
    error names `file` and `field` (default: the character's file)."""
    if partner not in character.feet or partner == foot:
        raise UserInputError(
            f"'{partner}' cannot be pinned with stance foot '{foot}'",
            file=file or character.path,
            field=field,
            fix=f"use other feet among: {', '.join(f for f in character.feet if f != foot)}",
        )
    return partner


def dof_labels(character: Character) -> list[str]:
    return [
        f"{j}:{'xyz'[a]}" if character.joint_dofs[j] == 3 else j
        for j in character.joints
        for a in range(character.joint_dofs[j])
    ]


def compute_modes(
    source: Character | World,
    phase: str = "air",
    foot: str | None = None,
    pose: str | dict = DEFAULT_POSE,
    partners: Sequence[str] = (),
) -> ModeSet:
    """Modes of a character (or an already built world) in the air (free) or ground (toe pinned)
    phase; in the ground phase the toes of `partners`, feet on the floor with the stance foot (a
    trot's diagonal partner), are pinned too. The basis of each eigenspace and the sign of each
    mode are canonical (`canonical_eigenspaces`, `canonical_signs`): rounding, which differs from
    one CPU's linear algebra to another's, changes neither."""
    if phase not in PHASES:
        raise UserInputError(f"unknown phase '{phase}'", field="phase", fix="use air or ground")
    if partners and phase != "ground":
        raise UserInputError(
            "partner feet are pinned only in the ground phase",
            field="partners",
            fix="use phase='ground', or give no partners",
        )
    world = (
        source
        if isinstance(source, World)
        else build_world(source, pose, WorldOptions(gravity=False))
    )
    character = world.character
    G = None
    if phase == "ground":
        foot = stance_foot(character, foot)
        pinned = [foot, *(partner_foot(character, foot, p) for p in partners)]
        G = np.vstack([point_jacobian(world, character.feet[f].toe) for f in pinned])
    else:
        foot = None
    lam, shapes, rigid = constrained_modes(stiffness_matrix(world), mass_matrix(world), G)
    shapes = canonical_eigenspaces(lam, shapes)
    shapes = shapes * canonical_signs(shapes[world.internal_qvel])
    return ModeSet(
        character=character.name,
        relax_pose=world.pose,
        phase=phase,
        foot=foot,
        dofs=character.internal_dofs,
        rigid_modes=rigid,
        frequencies_hz=frequencies_hz(lam),
        shapes=shapes,
        torque_basis=unit_torque_basis(shapes[world.internal_qvel]),
        dof_labels=dof_labels(character),
        partners=list(partners),
    )
