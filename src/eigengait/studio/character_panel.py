"""Character, relax pose and sketch files: what the animator loads, poses and saves."""

from __future__ import annotations

import viser

from eigengait.character import builtin_names
from eigengait.control.library import preset_names
from eigengait.studio.messages import Messages
from eigengait.studio.state import AUTOSAVE_NAME, SKETCH_SUFFIXES, StudioState

CUSTOM_POSE = "(rotations below)"


class CharacterPanel:
    def __init__(
        self, server: viser.ViserServer, state: StudioState, messages: Messages, gui_order: float
    ):
        self.server, self.state, self.messages = server, state, messages
        self.syncing = False
        gui = server.gui
        with gui.add_folder("Character and files", order=gui_order):
            self.summary = gui.add_markdown("")
            self.builtin = gui.add_dropdown("built-in", builtin_names(), initial_value="humanoid")
            self.path = gui.add_text(
                "file",
                "",
                hint=(
                    "an MJCF (.xml) or sketch (.yaml/.json) file inside the studio folder, or a "
                    "shipped sketch name"
                ),
            )
            self.load = gui.add_button("Load file", icon=viser.Icon.FOLDER_OPEN)
            self.pose = gui.add_dropdown("relax pose", ["default"], initial_value="default")
            self.rotations = gui.add_text(
                "rotations",
                "",
                hint=(
                    "per-joint rotations in degrees, joint frame: "
                    "left_thigh=0,-30,0;right_shin=45,0,0"
                ),
            )
            self.apply_rotations = gui.add_button("Apply rotations")
            self.save_name = gui.add_text("save sketch as", "my-gait.sketch.yaml")
            self.save = gui.add_button("Save sketch", icon=viser.Icon.DEVICE_FLOPPY)
            gui.add_markdown(
                f"Every change is autosaved to `{AUTOSAVE_NAME}`. Shipped sketches: "
                f"{', '.join(preset_names())}."
            )
        self.builtin.on_update(messages.guarded(self._on_builtin))
        self.load.on_click(messages.guarded(self._on_load))
        self.pose.on_update(messages.guarded(self._on_pose))
        self.apply_rotations.on_click(messages.guarded(self._on_rotations))
        self.save.on_click(messages.guarded(self._on_save))
        state.subscribe("model", self.sync)

    def _on_builtin(self, event: viser.GuiEvent) -> None:
        if not self.syncing and self.builtin.value != self.state.sketch.character:
            self.state.load_character(self.builtin.value)
            self.messages.info(
                f"Loaded the built-in character **{self.builtin.value}**.", event.client
            )

    def _on_load(self, event: viser.GuiEvent) -> None:
        text = self.path.value.strip()
        if text.lower().endswith(".xml"):
            self.state.load_character(text)
        else:
            self.state.load_sketch(text)
        self.messages.info(f"Loaded `{text}`.", event.client)

    def _on_pose(self, event: viser.GuiEvent) -> None:
        if not self.syncing and self.pose.value != CUSTOM_POSE:
            self.state.set_relax_pose(self.pose.value)
            self.messages.info(f"Relax pose **{self.pose.value}**: modes recomputed.", event.client)

    def _on_rotations(self, event: viser.GuiEvent) -> None:
        self.state.set_relax_pose(self.rotations.value)
        self.messages.info("Relax pose rotations applied: modes recomputed.", event.client)

    def _on_save(self, event: viser.GuiEvent) -> None:
        name, sandbox = self.save_name.value, self.state.sandbox
        path = sandbox.resolve(name, SKETCH_SUFFIXES)

        def save() -> None:
            self.state.save_sketch(name)
            self.messages.info(f"Saved the sketch to `{sandbox.relative(path)}`.", event.client)

        self.messages.write_asking(event.client, path, sandbox.relative(path), save)

    def sync(self) -> None:
        sketch, system = self.state.sketch, self.state.system
        self.syncing = True
        try:
            names = self.state.relax_pose_names()
            custom = not isinstance(sketch.relax_pose, str)
            self.pose.options = [*names, CUSTOM_POSE] if custom else names
            self.pose.value = CUSTOM_POSE if custom else sketch.relax_pose
            if custom:
                self.rotations.value = ";".join(
                    f"{j}={','.join(f'{v:g}' for v in (r if isinstance(r, list) else [r]))}"
                    for j, r in sketch.relax_pose.items()
                )
            if sketch.character in builtin_names():
                self.builtin.value = sketch.character
        finally:
            self.syncing = False
        where = (
            sketch.character
            if sketch.character in builtin_names()
            else f"`{self.state.sandbox.relative(sketch.character)}`"
        )
        self.summary.content = (
            f"**{system.character.name}** ({where}): {system.character.internal_dofs} internal "
            f"DOF, {system.mode_count('air')} air and {system.mode_count('ground')} ground modes; "
            f"feet {', '.join(system.feet)}{' (mirrored)' if system.mirror else ''}."
        )
