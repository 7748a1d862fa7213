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
    world = _modal_world(source, pose)
    foot = stance_foot(world.character, foot) if phase == "ground" else None
    lam, shapes, rigid = _solve(world, foot, partners)
    shapes = canonical_eigenspaces(lam, shapes)
    shapes = shapes * canonical_signs(shapes[world.internal_qvel])
    return ModeSet(
        character=world.character.name,
        relax_pose=world.pose,
        phase=phase,
        foot=foot,
        dofs=world.character.internal_dofs,
        rigid_modes=rigid,
        frequencies_hz=frequencies_hz(lam),
        shapes=shapes,
        torque_basis=unit_torque_basis(shapes[world.internal_qvel]),
        dof_labels=dof_labels(world.character),
        partners=list(partners),
    )


def solver_torque_basis(
    source: Character | World,
    phase: str = "air",
    foot: str | None = None,
    pose: str | dict = DEFAULT_POSE,
    partners: Sequence[str] = (),
) -> np.ndarray:
    """The torque basis as controller files of format 1 numbered their modes: the eigensolver's
    own vectors, each scaled to unit norm with its largest-magnitude entry positive. Where
    frequencies repeat or entries tie, which vectors these are depends on the machine's rounding:
    on the machine that saved such a file, they are the ones it was made in."""
    world = _modal_world(source, pose)
    foot = stance_foot(world.character, foot) if phase == "ground" else None
    _, shapes, _ = _solve(world, foot, partners)
    internal = shapes[world.internal_qvel]
    basis = internal / np.linalg.norm(internal, axis=0)
    signs = np.sign(basis[np.argmax(abs(basis), axis=0), np.arange(basis.shape[1])])
    return basis * np.where(signs == 0, 1, signs)


def _modal_world(source: Character | World, pose: str | dict) -> World:
    """`source` itself if it is a world, else the character at `pose` without gravity."""
    if isinstance(source, World):
        return source
    return build_world(source, pose, WorldOptions(gravity=False))


def _solve(world: World, foot: str | None, partners: Sequence[str]):
    """(λ, M-orthonormal shapes, rigid count) in the air (foot None) or with the toes of `foot` and
    its `partners` pinned, as the solver returns them."""
    G = None
    if foot is not None:
        pinned = [foot, *(partner_foot(world.character, foot, p) for p in partners)]
        G = np.vstack([point_jacobian(world, world.character.feet[f].toe) for f in pinned])
    return constrained_modes(stiffness_matrix(world), mass_matrix(world), G)
