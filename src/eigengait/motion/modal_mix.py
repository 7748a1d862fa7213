"""Kinematic mode animation (Kry et al. 2009): q(t) = q_relax ⊕ Σ A_i φ_i sin(2π f_i t + ϕ_i).

Amplitudes A_i are modal coordinates in √kg·m, frequencies in Hz, phases in radians; the
displacement d(t) = Σ A_i φ_i sin(…) (nv, MuJoCo velocity coordinates) moves the relax pose as
`modal.shape_kinematics` describes. Relative amplitudes (the CLI's mix syntax) multiply the thesis's
equal-energy defaults (`modal.shape_kinematics.equal_energy_amplitudes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from math import gcd, lcm

import numpy as np

from eigengait.errors import UserInputError
from eigengait.modal.modeset import ModeSet
from eigengait.modal.shape_kinematics import (
    DEFAULT_MAX_ROTATION_DEG,
    displaced_qpos,
    equal_energy_amplitudes,
)
from eigengait.sim.world import World

MIX_SYNTAX = (
    "MODE:AMPLITUDE or MODE:AMPLITUDE@PHASE_DEGREES, comma separated, e.g. '1:0.5,3:0.3@90'"
)


@dataclass(frozen=True)
class ModeTerm:
    """One mode of a mix: user-facing mode number (1 = lowest), amplitude relative to the default,
    phase in degrees."""

    mode: int
    amplitude: float
    phase_deg: float = 0.0


@dataclass(frozen=True)
class ModalMix:
    """Σ A_i φ_i sin(2π f_i t + ϕ_i): shapes (nv × k), amplitudes in √kg·m, frequencies in Hz,
    phases in rad."""

    shapes: np.ndarray
    amplitudes: np.ndarray
    frequencies_hz: np.ndarray
    phases_rad: np.ndarray

    def displacement(self, times: np.ndarray) -> np.ndarray:
        """Generalized displacement (len(times) × nv) from the relax pose at the given times (s)."""
        arg = 2 * np.pi * np.outer(np.atleast_1d(times), self.frequencies_hz) + self.phases_rad
        return (np.sin(arg) * self.amplitudes) @ self.shapes.T

    def period(self) -> float | None:
        """Lowest common period (s) of the frequencies, or None if they are not commensurate
        (to 1e-9)."""
        return common_period(self.frequencies_hz)


def common_period(frequencies_hz: np.ndarray, max_denominator: int = 10_000) -> float | None:
    """Smallest T > 0 with f_i·T an integer for every i, or None if no such T exists with small
    denominators."""
    fractions = [Fraction(float(f)).limit_denominator(max_denominator) for f in frequencies_hz]
    if any(
        fr <= 0 or abs(float(fr) - f) > 1e-9 * max(f, 1.0)
        for fr, f in zip(fractions, frequencies_hz)
    ):
        return None
    numerator = 0
    denominator = 1
    for fr in fractions:
        numerator = gcd(numerator, fr.numerator)
        denominator = lcm(denominator, fr.denominator)
    return denominator / numerator


def harmonic_frequencies(frequencies_hz: np.ndarray, base_hz: float) -> np.ndarray:
    """Each frequency moved to the nearest positive multiple of `base_hz`, so the mix loops every
    1/base_hz s."""
    if not base_hz > 0:
        raise UserInputError(f"base frequency {base_hz} Hz must be positive", field="base_hz")
    return np.maximum(1, np.round(np.asarray(frequencies_hz) / base_hz)) * base_hz


def parse_mix(text: str) -> list[ModeTerm]:
    """'1:0.5,3:0.3@90' → [ModeTerm(1, 0.5, 0), ModeTerm(3, 0.3, 90)]."""
    terms = []
    for item in filter(None, (s.strip() for s in text.split(","))):
        mode, sep, rest = item.partition(":")
        amplitude, _, phase = rest.partition("@")
        try:
            terms.append(
                ModeTerm(int(mode), float(amplitude), float(phase) if phase.strip() else 0.0)
            )
        except ValueError:
            raise UserInputError(
                f"cannot read mix term '{item}'", field="mix", fix=f"write {MIX_SYNTAX}"
            ) from None
        if not sep:
            raise UserInputError(
                f"mix term '{item}' has no amplitude", field="mix", fix=f"write {MIX_SYNTAX}"
            )
    if not terms:
        raise UserInputError("the mix names no mode", field="mix", fix=f"write {MIX_SYNTAX}")
    return terms


def build_mix(
    world: World,
    modes: ModeSet,
    terms: list[ModeTerm],
    max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG,
    base_hz: float | None = None,
) -> ModalMix:
    """The mix of the given terms, amplitudes relative to the equal-energy default; optionally on
    harmonics."""
    for term in terms:
        if not 1 <= term.mode <= modes.count:
            raise UserInputError(
                f"mode {term.mode} does not exist",
                field="mix",
                fix=f"{modes.character} has modes 1..{modes.count} in the {modes.phase} phase",
            )
    index = np.array([t.mode - 1 for t in terms])
    default = equal_energy_amplitudes(world, modes, max_rotation_deg)
    frequencies = modes.frequencies_hz[index]
    if base_hz is not None:
        frequencies = harmonic_frequencies(frequencies, base_hz)
    return ModalMix(
        shapes=modes.shapes[:, index],
        amplitudes=np.array([t.amplitude for t in terms]) * default[index],
        frequencies_hz=frequencies,
        phases_rad=np.deg2rad([t.phase_deg for t in terms]),
    )


def mix_trajectory(
    world: World, mix: ModalMix, seconds: float, fps: float
) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and qpos (T × nq) of the mix sampled at `fps` frames per second for `seconds`
    (t = 0 included)."""
    if not (seconds > 0 and fps > 0):
        raise UserInputError(
            f"need positive duration and frame rate, got {seconds} s at {fps} fps",
            field="seconds/fps",
        )
    times = np.arange(int(round(seconds * fps)) + 1) / fps
    return times, displaced_qpos(world, mix.displacement(times))
