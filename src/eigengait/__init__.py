"""eigengait: physics-based character animation from natural vibration modes."""

__version__ = "0.1.0"
