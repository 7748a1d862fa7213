"""Characters: an MJCF file with a free-joint root, stiff ball/hinge joints, and optional sidecar
metadata."""

from eigengait.character.library import builtin_names, resolve_character
from eigengait.character.loader import Character, load_character

__all__ = ["Character", "builtin_names", "load_character", "resolve_character"]
