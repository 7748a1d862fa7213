"""Natural vibration modes of a character about its relax pose (air and ground phases)."""

from eigengait.modal.analysis import compute_modes
from eigengait.modal.modeset import ModeSet

__all__ = ["ModeSet", "compute_modes"]
