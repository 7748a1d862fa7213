"""Kinematic mode animation (Kry et al. 2009): q(t) = q_relax ⊕ Σ A_i φ_i sin(2π f_i t + ϕ_i).

Units and frames:

* φ_i are the ModeSet's mass-normalized shapes (φᵀMφ = 1) in MuJoCo velocity coordinates, so an amplitude A_i is a
  modal coordinate in √kg·m (equivalently, A_i² is twice the kinetic energy per ω_i², in kg·m²).
* The displacement d(t) = Σ A_i φ_i sin(…) (nv) is applied to the relax pose with `mj_integratePos(qpos0, d, 1)`:
  root translation in world metres, root and ball-joint rotations as rotation vectors in radians.
* Default amplitudes follow the thesis's equal-energy rule E = ½ k_i A_i² with k_i = ω_i² (unit modal mass): every
  mode gets the same energy, so A_i ∝ 1/ω_i and low modes swing wider. The common energy is set so that the mode
  with the largest joint rotation at that energy turns its joint by `max_rotation_deg`; no single mode at its
  default amplitude turns any joint further. Relative amplitudes (the CLI's mix syntax) multiply these defaults.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from math import gcd, lcm

import mujoco
import numpy as np

from eigengait.errors import UserInputError
from eigengait.modal.modeset import ModeSet
from eigengait.sim.world import World

DEFAULT_MAX_ROTATION_DEG = 25.0
MIX_SYNTAX = "MODE:AMPLITUDE or MODE:AMPLITUDE@PHASE_DEGREES, comma separated, e.g. '1:0.5,3:0.3@90'"


@dataclass(frozen=True)
class ModeTerm:
    """One mode of a mix: user-facing mode number (1 = lowest), amplitude relative to the default, phase in degrees."""

    mode: int
    amplitude: float
    phase_deg: float = 0.0


@dataclass(frozen=True)
class ModalMix:
    """Σ A_i φ_i sin(2π f_i t + ϕ_i): shapes (nv × k), amplitudes in √kg·m, frequencies in Hz, phases in rad."""

    shapes: np.ndarray
    amplitudes: np.ndarray
    frequencies_hz: np.ndarray
    phases_rad: np.ndarray

    def displacement(self, times: np.ndarray) -> np.ndarray:
        """Generalized displacement (len(times) × nv) from the relax pose at the given times (s)."""
        arg = 2 * np.pi * np.outer(np.atleast_1d(times), self.frequencies_hz) + self.phases_rad
        return (np.sin(arg) * self.amplitudes) @ self.shapes.T

    def period(self) -> float | None:
        """Lowest common period (s) of the frequencies, or None if they are not commensurate (to 1e-9)."""
        return common_period(self.frequencies_hz)


def common_period(frequencies_hz: np.ndarray, max_denominator: int = 10_000) -> float | None:
    """Smallest T > 0 with f_i·T an integer for every i, or None if no such T exists with small denominators."""
    fractions = [Fraction(float(f)).limit_denominator(max_denominator) for f in frequencies_hz]
    if any(fr <= 0 or abs(float(fr) - f) > 1e-9 * max(f, 1.0) for fr, f in zip(fractions, frequencies_hz)):
        return None
    numerator = 0
    denominator = 1
    for fr in fractions:
        numerator = gcd(numerator, fr.numerator)
        denominator = lcm(denominator, fr.denominator)
    return denominator / numerator


def harmonic_frequencies(frequencies_hz: np.ndarray, base_hz: float) -> np.ndarray:
    """Each frequency moved to the nearest positive multiple of `base_hz`, so the mix loops every 1/base_hz s."""
    if not base_hz > 0:
        raise UserInputError(f"base frequency {base_hz} Hz must be positive", field="base_hz")
    return np.maximum(1, np.round(np.asarray(frequencies_hz) / base_hz)) * base_hz


def joint_rotations(world: World, displacement: np.ndarray) -> np.ndarray:
    """Rotation angle (rad) of each internal joint for displacements (nv × k) → (n_joints × k)."""
    model = world.model
    d = displacement.reshape(model.nv, -1)
    angles = []
    for j in world.internal_qpos_joints:
        adr = model.jnt_dofadr[j]
        n = 3 if model.jnt_type[j] == mujoco.mjtJoint.mjJNT_BALL else 1
        angles.append(np.linalg.norm(d[adr : adr + n], axis=0))
    return np.array(angles)


def equal_energy_amplitudes(
    world: World, modes: ModeSet, max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG
) -> np.ndarray:
    """Default amplitude of every mode (√kg·m): A_i = c/ω_i, c such that the widest mode reaches the angle."""
    omega = 2 * np.pi * modes.frequencies_hz
    peak = joint_rotations(world, modes.shapes / omega).max(axis=0)
    return np.deg2rad(max_rotation_deg) / peak.max() / omega


def peak_rotation_amplitudes(
    world: World, modes: ModeSet, max_rotation_deg: float = DEFAULT_MAX_ROTATION_DEG
) -> np.ndarray:
    """Amplitude of each mode (√kg·m) that turns its most-moving joint by exactly the angle (for display)."""
    peak = joint_rotations(world, modes.shapes).max(axis=0)
    return np.deg2rad(max_rotation_deg) / peak


def parse_mix(text: str) -> list[ModeTerm]:
    """'1:0.5,3:0.3@90' → [ModeTerm(1, 0.5, 0), ModeTerm(3, 0.3, 90)]."""
    terms = []
    for item in filter(None, (s.strip() for s in text.split(","))):
        mode, sep, rest = item.partition(":")
        amplitude, _, phase = rest.partition("@")
        try:
            terms.append(ModeTerm(int(mode), float(amplitude), float(phase) if phase.strip() else 0.0))
        except ValueError:
            raise UserInputError(f"cannot read mix term '{item}'", field="mix", fix=f"write {MIX_SYNTAX}") from None
        if not sep:
            raise UserInputError(f"mix term '{item}' has no amplitude", field="mix", fix=f"write {MIX_SYNTAX}")
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
    """The mix of the given terms, amplitudes relative to the equal-energy default; optionally on harmonics."""
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


def displaced_qpos(world: World, displacement: np.ndarray) -> np.ndarray:
    """Relax pose moved by generalized displacements (T × nv) → qpos (T × nq)."""
    model = world.model
    frames = np.tile(model.qpos0, (len(displacement), 1))
    for qpos, d in zip(frames, displacement):
        mujoco.mj_integratePos(model, qpos, d, 1.0)
    return frames


def mix_trajectory(world: World, mix: ModalMix, seconds: float, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Times (s) and qpos (T × nq) of the mix sampled at `fps` frames per second for `seconds` (t = 0 included)."""
    if not (seconds > 0 and fps > 0):
        raise UserInputError(
            f"need positive duration and frame rate, got {seconds} s at {fps} fps", field="seconds/fps"
        )
    times = np.arange(int(round(seconds * fps)) + 1) / fps
    return times, displaced_qpos(world, mix.displacement(times))
