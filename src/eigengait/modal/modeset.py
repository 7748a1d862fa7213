"""ModeSet: a character's vibration modes in one phase, saved and loaded as `.npz`.

* `frequencies_hz` (m,): non-rigid modes, ascending; user-facing mode numbers start at 1
  (index 0 → mode 1).
* `shapes` (nv × m): mass-normalized generalized displacements (φᵀ M φ = 1), MuJoCo velocity
  coordinates.
* `torque_basis` (n_internal × m): the internal-dof part of each shape scaled to unit Euclidean
  norm, so a mode activation ψ is in N·m. Sign convention (shapes and torque basis alike): of the
  column's entries within SIGN_TIE of its largest magnitude, the first in dof order is positive (a
  symmetric character's left and right joints tie; rounding must not pick between them).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from eigengait.errors import UserInputError
from eigengait.outputs import replacing

FORMAT_VERSION = 1
# entries within this share of a column's largest magnitude tie with it for the sign convention
SIGN_TIE = 1e-6


@dataclass
class ModeSet:
    character: str
    relax_pose: str | dict
    phase: str  # "air" or "ground"
    foot: str | None  # stance foot for the ground phase
    dofs: int  # internal degrees of freedom
    rigid_modes: int  # zero modes dropped (6 in the air, 3 with a pinned toe)
    frequencies_hz: np.ndarray
    shapes: np.ndarray
    torque_basis: np.ndarray
    dof_labels: list[str] = field(default_factory=list)  # "joint:x" for each internal dof
    # feet whose toes are pinned with the stance foot's in the ground phase (a trot's diagonal pair)
    partners: list[str] = field(default_factory=list)

    @property
    def count(self) -> int:
        return len(self.frequencies_hz)

    @property
    def pinned_feet(self) -> list[str]:
        """The feet whose toes are pinned: none in the air phase."""
        return [self.foot, *self.partners] if self.foot else []

    def pinned_text(self) -> str:
        """E.g. "left toe pinned", "rear_left + front_right toes pinned"; "" in the air."""
        feet = self.pinned_feet
        if not feet:
            return ""
        return " + ".join(feet) + (" toe pinned" if len(feet) == 1 else " toes pinned")

    def summary(self) -> dict:
        """The JSON object the CLI prints."""
        return {
            "character": self.character,
            "relax_pose": self.relax_pose,
            "phase": self.phase,
            "foot": self.foot,
            "partners": list(self.partners),
            "dofs": self.dofs,
            "rigid_modes": self.rigid_modes,
            "frequencies_hz": [round(float(f), 6) for f in self.frequencies_hz],
        }

    def save(self, path: str | Path) -> None:
        """Write the mode set as .npz (through a temporary file and a rename)."""
        meta = {k: v for k, v in asdict(self).items() if not isinstance(v, np.ndarray)}
        with replacing(path) as temporary, open(temporary, "wb") as f:
            np.savez(
                f,
                meta=json.dumps({"eigengait_modeset": FORMAT_VERSION, **meta}),
                frequencies_hz=self.frequencies_hz,
                shapes=self.shapes,
                torque_basis=self.torque_basis,
            )

    @classmethod
    def load(cls, path: str | Path) -> "ModeSet":
        try:
            with np.load(Path(path), allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                arrays = {k: z[k] for k in ("frequencies_hz", "shapes", "torque_basis")}
        except (OSError, ValueError, KeyError) as exc:
            raise UserInputError(
                f"not a mode-set file ({exc})", file=path, fix="recompute it with `eigengait modes`"
            ) from None
        if meta.pop("eigengait_modeset", None) != FORMAT_VERSION:
            raise UserInputError(
                "unsupported mode-set version", file=path, field="eigengait_modeset"
            )
        return cls(**meta, **arrays)


def canonical_signs(columns: np.ndarray) -> np.ndarray:
    """±1 per column: the sign that makes the column's leading entry positive, the leading entry
    being the first (in row order) of those within SIGN_TIE of the largest magnitude."""
    magnitude = abs(columns)
    leading = np.argmax(magnitude >= (1 - SIGN_TIE) * magnitude.max(axis=0), axis=0)
    signs = np.sign(columns[leading, np.arange(columns.shape[1])])
    return np.where(signs == 0, 1.0, signs)


def unit_torque_basis(shapes_internal: np.ndarray) -> np.ndarray:
    """Columns scaled to unit norm, signed by `canonical_signs`."""
    norms = np.linalg.norm(shapes_internal, axis=0)
    basis = shapes_internal / np.where(norms > 0, norms, 1)
    return basis * canonical_signs(basis)
