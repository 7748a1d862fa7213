"""Controller and sketch files of format 1 in today's mode bases.

Format 1 numbered a gait's modes in the eigensolver's own vectors
(`modal.analysis.solver_torque_basis`): where frequencies repeat (twin limbs) or a mode's left and
right entries tie, those vectors are whatever the machine's rounding made them. Format 2 numbers
them in the canonical bases (`modal.analysis.compute_modes`). On the machine reading it,
`in_canonical_modes` re-expresses a format-1 controller's activations and modal gains as the same
torques in the canonical bases (the file plays here what it played here before), and
`mode_signs` gives the signs that re-sign a format-1 sketch's priority activations
(`control.sketch.load_sketch`).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from eigengait.character import load_character
from eigengait.character.loader import Character
from eigengait.control.feedback import EventGains, FeedbackGains
from eigengait.control.gait import GaitParameters, GaitSystem, free_feet
from eigengait.errors import UserInputError
from eigengait.modal.analysis import compute_modes, solver_torque_basis
from eigengait.sim.world import WorldOptions, build_world

LEGACY_FORMAT = 1
# entries of a change of basis this close to 0 or ±1 are rounding of exactly those
EXACT = 1e-9


def mode_transforms(
    character: Character, pose: str | dict, feet: list[str], partners: dict[str, list[str]]
) -> dict[tuple[str, str], np.ndarray]:
    """Per (phase, foot of `feet`): T (m × m) with canonical ψ = T · format-1 ψ, the same torques
    (`partners`: each foot's stance partners)."""
    world = build_world(character, pose, WorldOptions(gravity=False, floor=False))
    out = {}
    for foot in feet:
        for phase in ("air", "ground"):
            stance = foot if phase == "ground" else None
            pinned = partners.get(foot, ()) if stance else ()
            legacy = solver_torque_basis(world, phase, stance, partners=pinned)
            canonical = compute_modes(world, phase, stance, partners=pinned).torque_basis
            T, *_ = np.linalg.lstsq(canonical, legacy, rcond=None)
            for exact in (0.0, 1.0, -1.0):
                T[abs(T - exact) < EXACT] = exact
            out[(phase, foot)] = T
    return out


def _shared(T: dict, phase: str, feet: list[str], source, field: str) -> np.ndarray:
    """The one change of basis of `phase` for every foot of `feet` (numbers of that phase are
    shared by them); an error naming `source` and `field` where the feet's bases changed apart."""
    first, *others = (T[(phase, foot)] for foot in feet)
    if any(not np.array_equal(first, other) for other in others):
        raise UserInputError(
            f"the {phase} modes of the feet {', '.join(feet)} changed differently with the "
            "canonical mode bases, so their shared numbers cannot be re-expressed",
            file=source,
            field=field,
            fix="mark the file format 2 and check its signs against `eigengait palette`, or make "
            "it again (`eigengait sketch new`, `eigengait optimize`)",
        )
    return first


def in_canonical_modes(
    p: GaitParameters, system: GaitSystem, source: str | Path | None = None
) -> GaitParameters:
    """`p`, read from a format-1 file, with its activations and modal gains in the canonical
    bases. Gains are shared by every foot of a phase, so feet whose bases changed differently
    cannot share them: an error naming `source`."""
    if system.basis != "modal":
        return p
    feet = system.active_feet
    T = mode_transforms(system.character, system.pose, feet, system.stance_partners)
    activations = {key: T[(key[1], key[0])] @ psi for key, psi in p.activations.items()}

    def gains(rows: dict[str, tuple[list[int], np.ndarray]]) -> dict:
        out = {}
        for phase, (modes, K) in rows.items():
            transform = _shared(T, phase, feet, source, "feedback")
            dense = np.zeros((transform.shape[1], K.shape[1]))
            dense[np.asarray(modes) - 1] = K
            moved = transform @ dense
            kept = np.flatnonzero(np.any(moved != 0, axis=1))
            out[phase] = ([int(m) + 1 for m in kept], moved[kept])
        return out

    event = p.feedback.event
    feedback = FeedbackGains(
        hip=p.feedback.hip,
        modal=gains(p.feedback.modal),
        event=None if event is None else EventGains(speed=event.speed, phases=gains(event.phases)),
    )
    return replace(p, activations=activations, feedback=feedback)


def mode_signs(
    character_name: str,
    pose: str | dict,
    feet: list[str] | None,
    symmetric: bool,
    partners: dict[str, list[str]],
    source: str | Path | None = None,
) -> dict[str, np.ndarray]:
    """Per phase, ±1 per mode: −1 where the canonical basis flipped that mode's sign alone (a
    sketch's feet; none: the character's gait order). A mode of a repeated frequency gets 1: it
    names another vector of the same eigenspace, which no sign re-expresses."""
    character = load_character(character_name)
    feet = feet or character.meta.gait_order
    active = free_feet(feet, symmetric)
    T = mode_transforms(character, pose, active, partners)
    out = {}
    for phase in ("air", "ground"):
        transform = _shared(T, phase, active, source, f"{phase}.priority")
        diagonal = np.diag(transform)
        alone = (np.count_nonzero(transform, axis=0) == 1) & (abs(diagonal) == 1.0)
        out[phase] = np.where(alone, diagonal, 1.0)
    return out
