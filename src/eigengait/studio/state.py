"""The one studio state every browser tab shares: the character, its modes, the sketch being edited.

Every change goes through a method here, under one lock, and is followed by an autosave of the
sketch to `studio-autosave.sketch.yaml` in the studio folder (the same format
`eigengait sketch/optimize` read), so a dropped connection or a restarted studio loses nothing.
Views subscribe to two events: `model` (character or relax pose changed, modes recomputed) and
`sketch` (statuses, activations or timing changed).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable
from pathlib import Path

from eigengait.character import builtin_names, load_character
from eigengait.character.relax import parse_relax_argument
from eigengait.control.binding import gait_system, mode_counts
from eigengait.files import dump
from eigengait.control.gait import GaitSystem
from eigengait.control.library import preset_names, resolve
from eigengait.control.sketch import Sketch, check_modes, load_sketch
from eigengait.errors import UserInputError
from eigengait.modal.modeset import ModeSet
from eigengait.studio.model_files import confine_character
from eigengait.studio.sandbox import Sandbox

AUTOSAVE_NAME = "studio-autosave.sketch.yaml"
STATUSES = ("priority", "allowed", "excluded")
DEFAULT_ACTIVATION = 20.0  # N·m given to a mode when it is first marked priority
NEW_SKETCH_ALLOWED = 12  # a new sketch allows the lowest modes (the thesis's "trivial selection")
SKETCH_SUFFIXES = (".yaml", ".yml", ".json")


class StudioState:
    def __init__(self, sandbox: Sandbox):
        self.sandbox = sandbox
        self.lock = threading.RLock()
        self.sketch: Sketch | None = None
        # the sketch's system with gravity off: modes and sketch simulation
        self.system: GaitSystem | None = None
        self._listeners: dict[str, list[Callable[[], None]]] = {"model": [], "sketch": []}

    @property
    def autosave_path(self) -> Path:
        return self.sandbox.root / AUTOSAVE_NAME

    def subscribe(self, event: str, callback: Callable[[], None]) -> None:
        self._listeners[event].append(callback)

    def _notify(self, *events: str) -> None:
        for event in events:
            for callback in self._listeners[event]:
                callback()

    # ---- opening ---------------------------------------------------------------------------------
    def open(self, target: str | None) -> None:
        """Start on a built-in character, a shipped sketch, an MJCF or sketch file; else the
        autosave or humanoid."""
        if target:
            is_sketch = target in preset_names() or target.lower().endswith(SKETCH_SUFFIXES)
            self.load_sketch(target) if is_sketch else self.load_character(target)
        elif self.autosave_path.is_file():
            self.load_sketch(AUTOSAVE_NAME)
        else:
            self.load_character("humanoid")

    def character_reference(self, text: str) -> str:
        """A built-in name as is, or the absolute path of an MJCF file inside the studio folder that
        reads no file outside it."""
        text = text.strip()
        if text in builtin_names():
            return text
        if Path(text).is_absolute() and self.sandbox.contains(text):
            text = self.sandbox.relative(Path(text))
        path = self.sandbox.resolve(text, (".xml",), must_exist=True)
        confine_character(self.sandbox, path)
        return str(path)

    def load_character(self, text: str) -> None:
        """A fresh sketch for a character: lowest modes allowed, the rest excluded, no priority
        yet."""
        reference = self.character_reference(text)
        character = load_character(reference)
        feet = character.meta.gait_order or list(character.feet)
        symmetric = len(feet) == 2 and character.meta.mirror is not None
        air = {"allowed": list(range(1, NEW_SKETCH_ALLOWED + 1))}
        sketch = Sketch(
            character=reference, feet=feet or None, symmetric=symmetric, air=air, ground=air
        )
        self._install(sketch, clip=True)

    def load_sketch(self, text: str) -> None:
        """A shipped preset by name, or a sketch file inside the studio folder."""
        if text.strip() in preset_names():
            path = resolve("sketch", text.strip())
        else:
            path = self.sandbox.resolve(text, SKETCH_SUFFIXES, must_exist=True)
        sketch = load_sketch(path)
        sketch.character = self.character_reference(sketch.character)
        self._install(sketch, clip=False)

    def set_relax_pose(self, text: str) -> None:
        """A preset name, `default`, or rotations `joint=rx,ry,rz;…` in degrees; modes are
        recomputed."""
        with self.lock:
            data = self.sketch.model_dump()
        data["relax_pose"] = parse_relax_argument(text)
        self._install(Sketch.model_validate(data), clip=True)

    def _install(self, sketch: Sketch, clip: bool) -> None:
        """Bind a sketch to its character (recomputing modes) and make it current; nothing changes
        on error."""
        system = gait_system(sketch, gravity=False)
        if clip:
            sketch = _clipped(sketch, system)
        check_modes(sketch, mode_counts(system))
        with self.lock:
            self.sketch, self.system = sketch, system
            self.autosave()
        self._notify("model", "sketch")

    # ---- reading ---------------------------------------------------------------------------------
    def modes(self, phase: str) -> ModeSet:
        """The palette's modes: air, or ground with the first stance foot's toe pinned."""
        system = self.system
        return system.air_modes if phase == "air" else system.ground_modes[system.feet[0]]

    def relax_pose_names(self) -> list[str]:
        return ["default", *self.system.character.meta.relax_poses]

    def status(self, phase: str, mode: int) -> str:
        p = self.sketch.phase(phase)
        if mode in p.priority:
            return "priority"
        if mode in p.excluded or (p.allowed is not None and mode not in p.allowed):
            return "excluded"
        return "allowed"

    # ---- editing ---------------------------------------------------------------------------------
    def set_status(self, phase: str, mode: int, status: str) -> None:
        if status not in STATUSES:
            raise UserInputError(
                f"unknown mode status '{status}'", fix=f"use one of: {', '.join(STATUSES)}"
            )
        with self.lock:
            count = self.modes(phase).count
            statuses = {m: self.status(phase, m) for m in range(1, count + 1)}
            statuses[mode] = status
            priority = {
                m: v
                for m, v in self.sketch.phase(phase).priority.items()
                if statuses[m] == "priority"
            }
            if status == "priority" and mode not in priority:
                priority[mode] = DEFAULT_ACTIVATION
            self._edit(
                {
                    phase: {
                        "priority": priority,
                        "allowed": [m for m, s in statuses.items() if s == "allowed"],
                        "excluded": [m for m, s in statuses.items() if s == "excluded"],
                    }
                }
            )

    def set_activation(self, phase: str, mode: int, psi: float) -> None:
        """Priority activation ψ (N·m) of a priority mode; zero is refused (it would make the mode
        unused)."""
        if psi == 0:
            raise UserInputError(
                f"priority mode {mode} needs a non-zero activation",
                fix="give it a positive or negative ψ, or mark it allowed",
            )
        with self.lock:
            if mode not in self.sketch.phase(phase).priority:
                raise UserInputError(
                    f"{phase} mode {mode} is not a priority mode", fix="mark it priority first"
                )
            priority = {**self.sketch.phase(phase).priority, mode: float(psi)}
            self._edit({phase: {**self.sketch.phase(phase).model_dump(), "priority": priority}})

    def set_timing(self, **values: float) -> None:
        """Period T (s), air ratio α, pulse durations δa, δc (s)."""
        with self.lock:
            self._edit({"timing": {**self.sketch.timing.model_dump(), **values}})

    def _edit(self, changes: dict) -> None:
        with self.lock:
            data = {**self.sketch.model_dump(), **changes}
            try:
                sketch = Sketch.model_validate(data)
            except ValueError as err:
                raise UserInputError(str(err).splitlines()[-1].strip()) from None
            self.sketch = sketch
            self.autosave()
        self._notify("sketch")

    # ---- files -----------------------------------------------------------------------------------
    def save_sketch(self, text: str) -> Path:
        path = self.sandbox.resolve(text, SKETCH_SUFFIXES)
        with self.lock:
            write_sketch(self.sketch, path)
        return path

    def autosave(self) -> None:
        write_sketch(self.sketch, self.autosave_path)


def write_sketch(sketch: Sketch, path: Path) -> None:
    """Save a sketch; a character file is written relative to the sketch file, as `load_sketch`
    expects."""
    if Path(sketch.character).is_absolute():
        sketch = sketch.model_copy(
            update={"character": os.path.relpath(sketch.character, path.parent)}
        )
    dump(sketch, path)


def _clipped(sketch: Sketch, system: GaitSystem) -> Sketch:
    """The sketch with mode numbers the character does not have dropped."""
    data = sketch.model_dump()
    for phase in ("air", "ground"):
        count = system.mode_count(phase)
        p = data[phase]
        p["priority"] = {m: v for m, v in p["priority"].items() if m <= count}
        p["allowed"] = None if p["allowed"] is None else [m for m in p["allowed"] if m <= count]
        p["excluded"] = [m for m in p["excluded"] if m <= count]
    return Sketch.model_validate(data)
