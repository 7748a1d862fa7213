"""Controller files of format 1 in today's mode bases.

Format 1 numbered a gait's modes in the eigensolver's own vectors
(`modal.analysis.solver_torque_basis`): where frequencies repeat (twin limbs) or a mode's left and
right entries tie, those vectors are whatever the machine's rounding made them. Format 2 numbers
them in the canonical bases (`modal.analysis.compute_modes`). `in_canonical_modes` re-expresses a
format-1 controller's activations and modal gains, on the machine reading it, as the same torques
in the canonical bases: the file plays here what it played here before.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from eigengait.control.feedback import EventGains, FeedbackGains
from eigengait.control.gait import GaitParameters, GaitSystem
from eigengait.errors import UserInputError
from eigengait.modal.analysis import solver_torque_basis
from eigengait.sim.world import WorldOptions, build_world

LEGACY_FORMAT = 1
# entries of a change of basis this close to 0 or ±1 are rounding of exactly those
EXACT = 1e-9


def mode_transforms(system: GaitSystem) -> dict[tuple[str, str], np.ndarray]:
    """Per (phase, active foot): T (m × m) with canonical ψ = T · format-1 ψ, the same torques."""
    world = build_world(system.character, system.pose, WorldOptions(gravity=False, floor=False))
    out = {}
    for foot in system.active_feet:
        for phase in ("air", "ground"):
            legacy = solver_torque_basis(
                world,
                phase,
                foot if phase == "ground" else None,
                partners=system.stance_partners.get(foot, ()),
            )
            T, *_ = np.linalg.lstsq(system.basis_matrix(foot, phase), legacy, rcond=None)
            for exact in (0.0, 1.0, -1.0):
                T[abs(T - exact) < EXACT] = exact
            out[(phase, foot)] = T
    return out


def in_canonical_modes(
    p: GaitParameters, system: GaitSystem, source: str | Path | None = None
) -> GaitParameters:
    """`p`, read from a format-1 file, with its activations and modal gains in the canonical
    bases. Gains are shared by every foot of a phase, so feet whose bases changed differently
    cannot share them: an error naming `source`."""
    if system.basis != "modal":
        return p
    T = mode_transforms(system)
    activations = {key: T[(key[1], key[0])] @ psi for key, psi in p.activations.items()}

    def phase_transform(phase: str) -> np.ndarray:
        first, *others = (T[(phase, foot)] for foot in system.active_feet)
        if any(not np.array_equal(first, other) for other in others):
            raise UserInputError(
                f"the {phase} modes of this controller's feet changed differently with the "
                "canonical mode bases, so their shared feedback gains cannot be re-expressed",
                file=source,
                field="feedback",
                fix="optimize the gait again (`eigengait optimize`), or remove its modal feedback",
            )
        return first

    def gains(rows: dict[str, tuple[list[int], np.ndarray]]) -> dict:
        out = {}
        for phase, (modes, K) in rows.items():
            transform = phase_transform(phase)
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
