"""The sidecar metadata file `<model>.eigengait.yaml` beside a character's MJCF (optional,
validated).

```yaml
eigengait: 1                     # format version
model: ../models/walker.xml      # optional: the MJCF this sidecar describes (relative to the sidecar), which makes
                                 # the sidecar itself a CHARACTER argument; without it the sidecar sits beside the MJCF
body: torso                      # optional: the creature's root body in a scene with several (default: the largest)
feet:                            # foot name -> MJCF site names of its toe and heel points
  left: {toe: left_toe, heel: left_heel}
gait_order: [left, right]        # order in which feet take the ground in a gait cycle
mirror:                          # left/right symmetry through the plane normal to `axis` (body frames)
  axis: y
  pairs: {left_thigh: right_thigh}
stiffness:                       # joint stiffness in N·m/rad, joint frame: (kx, ky, kz) for a ball, k for a hinge;
  torso: [500, 800, 300]         # `auto` instead of a mapping: the sag rule (see `character/stiffness.py`)
  knee: 120
damping_ratio: 0.1               # damping = damping_ratio × stiffness (s)
strength: 1.0                    # rad: each motor's torque limit is its dof's stiffness × this angle (default: none)
relax_poses:                     # named relax poses: joint -> rotation vector in degrees, joint frame
  crouched: {left_thigh: [0, -35, 0]}
```
Without a sidecar, feet are found from site pairs named `<foot>_toe` / `<foot>_heel`.
"""  # noqa: E501

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from eigengait.files import load_model

FORMAT_VERSION = 1


class Foot(BaseModel):
    model_config = ConfigDict(extra="forbid")
    toe: str
    heel: str | None = None


class MirrorSpec(BaseModel):
    model_config = ConfigDict(extra="forbid")
    axis: Literal["x", "y", "z"] = "y"
    pairs: dict[str, str] = Field(default_factory=dict)


class CharacterMetadata(BaseModel):
    """Validated content of a character sidecar file."""

    model_config = ConfigDict(extra="forbid")
    eigengait: int = FORMAT_VERSION
    model: str | None = None
    body: str | None = None
    feet: dict[str, Foot] = Field(default_factory=dict)
    gait_order: list[str] = Field(default_factory=list)
    mirror: MirrorSpec | None = None
    stiffness: dict[str, tuple[float, float, float] | float] | Literal["auto"] = Field(
        default_factory=dict
    )
    damping_ratio: float = Field(0.1, ge=0.0)
    strength: float | None = Field(None, gt=0.0)
    relax_poses: dict[str, dict[str, tuple[float, float, float] | float]] = Field(
        default_factory=dict
    )

    @field_validator("eigengait")
    @classmethod
    def _known_version(cls, v: int) -> int:
        if v != FORMAT_VERSION:
            raise ValueError(
                f"unsupported format version {v}; this eigengait reads version {FORMAT_VERSION}"
            )
        return v

    @field_validator("stiffness")
    @classmethod
    def _positive_stiffness(cls, v):
        for joint, k in ({} if v == "auto" else v).items():
            if min(k if isinstance(k, tuple) else (k,)) <= 0:
                raise ValueError(
                    f"stiffness of joint '{joint}' must be positive in every axis, got {list(k)}"
                )
        return v


SIDECAR_SUFFIX = ".eigengait.yaml"


def sidecar_path(mjcf: Path) -> Path:
    """The sidecar file that belongs to an MJCF file: `NAME.xml` -> `NAME.eigengait.yaml`."""
    return mjcf.with_name(mjcf.stem + SIDECAR_SUFFIX)


def is_sidecar(path: Path) -> bool:
    return path.name.endswith(SIDECAR_SUFFIX)


def load_metadata(path: Path) -> CharacterMetadata:
    """Read and validate a sidecar file (an empty one gives the defaults); raise UserInputError
    naming the file and field."""
    return load_model(
        CharacterMetadata,
        path,
        "see the sidecar format in the README (Characters)",
        allow_empty=True,
    )
