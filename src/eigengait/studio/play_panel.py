"""Play a controller on the ground with gravity, report speed and cycles, export BVH and video, save
a copy.

A controller is a shipped gait name or a controller JSON inside the studio folder (e.g. a run's
`best_controller.json`); the character it names must be built in or inside the folder too. Exports
are written at exactly EXPORT_FPS, BVH lengths in metres (the CLI's defaults).
"""

from __future__ import annotations

from pathlib import Path

import viser

from eigengait.character import builtin_names
from eigengait.control.binding import gait_system
from eigengait.control.controller import (
    ControllerFile,
    load_controller,
    save_controller,
    to_parameters,
)
from eigengait.control.library import gait_names, resolve
from eigengait.control.playback import PlaybackResult, play
from eigengait.errors import UserInputError
from eigengait.sim.world import World
from eigengait.studio.messages import Messages
from eigengait.studio.model_files import confine_character
from eigengait.studio.sandbox import Sandbox
from eigengait.studio.stage import Stage

EXPORT_FPS = 30.0  # frames/s of exported BVH and video (the CLI's --fps default), resampled by time


class PlayPanel:
    def __init__(
        self,
        server: viser.ViserServer,
        sandbox: Sandbox,
        stage: Stage,
        messages: Messages,
        gui_order: float,
    ):
        self.server, self.sandbox, self.stage, self.messages = server, sandbox, stage, messages
        self.controller: ControllerFile | None = None
        self.world: World | None = None
        self.result: PlaybackResult | None = None
        gui = server.gui
        with gui.add_folder("Play (gravity on)", order=gui_order, expand_by_default=False):
            self.path = gui.add_text(
                "controller",
                (gait_names() or [""])[0],
                hint="a shipped gait name or a controller .json inside the studio folder",
            )
            self.cycles = gui.add_number("cycles", 6, min=1, max=50, step=1)
            self.snap = gui.add_checkbox(
                "snap each cycle",
                False,
                hint="snap back to the initial state at each cycle end (the thesis's playback)",
            )
            self.play = gui.add_button("Play on the ground", icon=viser.Icon.WALK)
            self.report = gui.add_markdown("")
            self.bvh_name = gui.add_text("BVH file", "gait.bvh")
            self.export_bvh = gui.add_button("Export BVH", disabled=True)
            self.video_name = gui.add_text("video file", "gait.mp4")
            self.export_video = gui.add_button("Export video", disabled=True)
            self.copy_name = gui.add_text("save controller as", "my-gait.controller.json")
            self.save = gui.add_button(
                "Save controller", disabled=True, icon=viser.Icon.DEVICE_FLOPPY
            )
        self.play.on_click(messages.guarded(lambda e: self.play_file(self.path.value, e.client)))
        self.export_bvh.on_click(messages.guarded(self._on_bvh))
        self.export_video.on_click(messages.guarded(self._on_video))
        self.save.on_click(messages.guarded(self._on_save))

    def _controller_path(self, text: str) -> Path:
        text = str(text).strip()
        if text in gait_names():
            return resolve("gait", text)
        if Path(text).is_absolute() and self.sandbox.contains(text):
            text = self.sandbox.relative(Path(text))
        return self.sandbox.resolve(text, (".json",), must_exist=True)

    def play_file(
        self, text: str | Path, client: viser.ClientHandle | None = None
    ) -> PlaybackResult:
        """Load a controller, play it with gravity and show it on the stage with the camera
        following."""
        path = self._controller_path(str(text))
        controller = load_controller(path)
        if controller.character not in builtin_names():
            confine_character(self.sandbox, Path(controller.character))
        system = gait_system(controller, source=path)
        result = play(
            system,
            to_parameters(controller, system, path),
            int(self.cycles.value),
            snap=self.snap.value,
        )
        if len(result.qpos) == 0:
            raise UserInputError("the controller produced no motion", file=path)
        self.controller, self.world, self.result = controller, system.world, result
        self.path.value = str(text) if str(text) in gait_names() else self.sandbox.relative(path)
        self.stage.show("playback", system.world, result.qpos, result.fps, follow=True)
        self.report.content = (
            f"**{path.name}** on {system.character.name}: {result.mean_speed_mps:.2f} m/s forward, "
            f"{result.cycles_completed}/{int(self.cycles.value)} "
            f"cycles{' (fell)' if result.fell else ''}, cost of transport "
            f"{result.cost_of_transport:.3g}, cycle violation "
            f"{result.cycle_violation:.3g}{', snapped each cycle' if result.snapped else ''}."
        )
        for button in (self.export_bvh, self.export_video, self.save):
            button.disabled = False
        self.messages.info(f"Playing `{self.path.value}` with gravity.", client)
        return result

    def _played(self) -> PlaybackResult:
        if self.result is None:
            raise UserInputError("nothing has been played yet", fix="play a controller first")
        return self.result

    def _on_bvh(self, event: viser.GuiEvent) -> None:
        from eigengait.motion.bvh_export import write_trajectory_bvh

        result, world = self._played(), self.world
        path = self.sandbox.resolve(self.bvh_name.value, (".bvh",))

        def export() -> None:
            write_trajectory_bvh(world, result.qpos, result.fps, path, fps=EXPORT_FPS)
            self.messages.info(f"Wrote `{self.sandbox.relative(path)}`.", event.client)

        self.messages.write_asking(event.client, path, self.sandbox.relative(path), export)

    def _on_video(self, event: viser.GuiEvent) -> None:
        from eigengait.render.video import render_video

        result, world = self._played(), self.world
        path = self.sandbox.resolve(self.video_name.value, (".mp4", ".gif"))

        def export() -> None:
            self.messages.info(f"Rendering `{self.sandbox.relative(path)}` …", event.client)
            render_video(world, result.qpos, result.fps, path, fps=EXPORT_FPS)
            self.messages.info(f"Wrote `{self.sandbox.relative(path)}`.", event.client)

        self.messages.write_asking(event.client, path, self.sandbox.relative(path), export)

    def _on_save(self, event: viser.GuiEvent) -> None:
        self._played()
        controller = self.controller
        path = self.sandbox.resolve(self.copy_name.value, (".json",))

        def save() -> None:
            save_controller(controller, path)
            self.messages.info(
                f"Saved the controller to `{self.sandbox.relative(path)}`.", event.client
            )

        self.messages.write_asking(event.client, path, self.sandbox.relative(path), save)
