"""The mode palette: every air and ground mode of the character vibrating, one small copy per mode.

The copies stand on two walls behind the stage (air on the left, ground on the right), in frequency
order, left to right and top to bottom, each labelled "N · f Hz" (mode 1 = lowest non-rigid mode) in
text sized with the scene, so labels never run into each other at any zoom. A copy is coloured by
its status in the sketch: green priority, grey-blue allowed, red excluded (the legend stands under
each wall's title). Every copy loops its kinematic vibration ±A sin(2πt/LOOP_SECONDS), A turning the
mode's most-moving joint by 25°, so every mode is equally visible and equally paced; the label gives
the true natural frequency. All copies are one batched mesh, so a frame of the whole palette is one
message.

The GUI lists each phase's modes with a status dropdown, and an activation slider ψ (N·m) for
priority modes.
"""

from __future__ import annotations

import threading

import numpy as np
import viser

from eigengait.errors import UserInputError
from eigengait.modal.shape_kinematics import displaced_qpos, peak_rotation_amplitudes
from eigengait.studio.messages import Messages
from eigengait.studio.figures import UNIT_CUBE_FACES, UNIT_CUBE_VERTICES, Figure, place
from eigengait.studio.state import STATUSES, StudioState

PHASES = ("air", "ground")
STATUS_RGB = {
    "priority": np.array([40, 170, 70]),
    "allowed": np.array([140, 160, 195]),
    "excluded": np.array([215, 55, 50]),
}
LOOP_FRAMES = 24
LOOP_SECONDS = 1.6
COPY_SCALE = 0.45
COPY_YAW_DEG = -35.0
COLUMNS = 6
COLUMN_SPACING = 2.3  # copy widths (plus 0.2 m) from one copy to the next: room for a legible label
LABEL_HEIGHT = 0.13  # fraction of the column spacing: label text height in the scene
LEGEND = "green: priority  ·  grey-blue: allowed  ·  red: excluded"
LABEL_SCALE = {"title": 1.6, "legend": 1.25}  # relative to a mode label
WALL_X = -2.5  # m: the walls stand behind the stage
WALL_GAP = 1.2  # m: half the space between the two walls (the stage sits in it)
PSI_LIMIT = 200.0  # N·m: slider range ±


class PaletteView:
    def __init__(
        self, server: viser.ViserServer, state: StudioState, messages: Messages, gui_order: float
    ):
        self.server, self.state, self.messages = server, state, messages
        self.gui_order = gui_order
        self.lock = threading.Lock()
        self.mesh: viser.BatchedMeshHandle | None = None
        self.scene_nodes: list = []
        self.folders: dict[str, viser.GuiFolderHandle] = {}
        self.rows: dict[str, dict[int, tuple[viser.GuiDropdownHandle, viser.GuiSliderHandle]]] = {}
        self.copies: list[tuple[str, int]] = []  # (phase, mode) of each copy, in instance order
        self.positions = self.wxyzs = None  # LOOP_FRAMES × instances × 3 / 4
        self.syncing = False
        self.shown_frame = -1
        self.animate = server.gui.add_checkbox(
            "animate palette",
            True,
            order=gui_order - 0.05,
            hint="pause the mode animations (helps slow, GPU-less machines)",
        )
        state.subscribe("model", self.rebuild)
        state.subscribe("sketch", self.sync)

    # ---- scene -----------------------------------------------------------------------------------
    def rebuild(self) -> None:
        """Recompute every mode's loop and lay the palette out again (character or relax pose
        changed)."""
        world = self.state.system.world
        figure = Figure.of(world)
        low, high = figure.extent(world.model.qpos0[None])
        anchor = (low + high) / 2
        spacing = COPY_SCALE * np.array(
            [COLUMN_SPACING * (max(high[:2] - low[:2]) + 0.2), 1.45 * (high[2] - low[2])]
        )
        phase_t = np.sin(2 * np.pi * np.arange(LOOP_FRAMES) / LOOP_FRAMES)
        positions, wxyzs, copies, labels = [], [], [], []
        for side, phase in zip((-1, 1), PHASES):
            modes = self.state.modes(phase)
            amplitudes = peak_rotation_amplitudes(world, modes)
            rows = -(-modes.count // COLUMNS)
            width = (COLUMNS - 1) * spacing[0]
            for i in range(modes.count):
                row, col = divmod(i, COLUMNS)
                y = side * (WALL_GAP + width / 2) + (col - (COLUMNS - 1) / 2) * spacing[0]
                cell = np.array([WALL_X, y, (rows - row - 0.5) * spacing[1]])
                qpos = displaced_qpos(world, np.outer(phase_t, modes.shapes[:, i] * amplitudes[i]))
                p, q = place(*figure.poses(qpos), anchor, cell, COPY_SCALE, COPY_YAW_DEG)
                positions.append(p)
                wxyzs.append(q)
                copies.append((phase, i + 1))
                labels.append(
                    (
                        f"{phase}{i + 1}",
                        f"{i + 1} · {modes.frequencies_hz[i]:.1f} Hz",
                        cell - [0, 0, spacing[1] * 0.42],
                    )
                )
            title = f"{phase.upper()} phase modes" + (
                f" ({modes.pinned_text()})" if modes.foot else ""
            )
            top = rows * spacing[1]
            labels.append(
                (f"{phase}_title", title, [WALL_X, side * (WALL_GAP + width / 2), top + 0.4])
            )
            labels.append(
                (f"{phase}_legend", LEGEND, [WALL_X, side * (WALL_GAP + width / 2), top + 0.18])
            )
        with self.lock:
            self._clear_scene()
            self.copies = copies
            self.positions = np.concatenate(positions, axis=1)
            self.wxyzs = np.concatenate(wxyzs, axis=1)
            sizes = np.tile(figure.sizes * COPY_SCALE, (len(copies), 1))
            self.geom_shade = np.tile(figure.colors, (len(copies), 1))
            self.shown_frame = 0
            self.mesh = self.server.scene.add_batched_meshes_simple(
                "/palette/copies",
                UNIT_CUBE_VERTICES,
                UNIT_CUBE_FACES,
                batched_wxyzs=self.wxyzs[0],
                batched_positions=self.positions[0],
                batched_scales=sizes,
                batched_colors=self._colors(),
                flat_shading=True,
                lod="off",
                cast_shadow=False,
                receive_shadow=False,
            )
            height = LABEL_HEIGHT * spacing[0]
            for name, text, position in labels:
                self.scene_nodes.append(
                    self.server.scene.add_label(
                        f"/palette/labels/{name}",
                        text,
                        position=position,
                        anchor="top-center",
                        font_size_mode="scene",
                        font_scene_height=height * LABEL_SCALE.get(name.split("_")[-1], 1.0),
                    )
                )
        self._rebuild_gui()

    def _clear_scene(self) -> None:
        for node in [self.mesh, *self.scene_nodes]:
            if node is not None:
                node.remove()
        self.mesh, self.scene_nodes = None, []

    def _colors(self) -> np.ndarray:
        geoms = len(self.geom_shade) // len(self.copies)
        status = np.repeat(
            [STATUS_RGB[self.state.status(ph, m)] for ph, m in self.copies], geoms, axis=0
        )
        return (0.8 * status + 0.2 * self.geom_shade).astype(np.uint8)

    def tick(self, seconds: float) -> None:
        """Show the loop frame for wall-clock time `seconds` (sent only when it changes)."""
        with self.lock:
            k = int(seconds / LOOP_SECONDS * LOOP_FRAMES) % LOOP_FRAMES
            if self.mesh is None or not self.animate.value or k == self.shown_frame:
                return
            self.shown_frame = k
            self.mesh.batched_positions = self.positions[k]
            self.mesh.batched_wxyzs = self.wxyzs[k]

    # ---- GUI -------------------------------------------------------------------------------------
    def _rebuild_gui(self) -> None:
        for folder in self.folders.values():
            folder.remove()
        self.folders, self.rows = {}, {}
        for k, phase in enumerate(PHASES):
            modes = self.state.modes(phase)
            folder = self.server.gui.add_folder(
                f"{phase.capitalize()} modes ({modes.count})",
                order=self.gui_order + k / 10,
                expand_by_default=phase == "air",
            )
            self.folders[phase] = folder
            self.rows[phase] = {}
            with folder:
                for i, hz in enumerate(modes.frequencies_hz):
                    self.rows[phase][i + 1] = self._mode_row(phase, i + 1, hz)
        self.sync()

    def _mode_row(self, phase: str, mode: int, hz: float):
        status = self.server.gui.add_dropdown(
            f"{phase} {mode} · {hz:.2f} Hz",
            STATUSES,
            initial_value=self.state.status(phase, mode),
            hint=f"{phase}-phase mode {mode}: priority (green) keeps its activation "
            "sign and size, allowed may be used, excluded stays zero",
        )
        slider = self.server.gui.add_slider(
            f"ψ {phase} {mode} (N·m)", -PSI_LIMIT, PSI_LIMIT, 0.5, 1.0, visible=False
        )

        @status.on_update
        @self.messages.guarded
        def _(event: viser.GuiEvent) -> None:
            if not self.syncing:
                try:
                    self.state.set_status(phase, mode, status.value)
                except UserInputError:
                    self.sync()
                    raise

        @slider.on_update
        @self.messages.guarded
        def _(event: viser.GuiEvent) -> None:
            if not self.syncing:
                try:
                    self.state.set_activation(phase, mode, slider.value)
                except UserInputError:
                    self.sync()
                    raise

        return status, slider

    def sync(self) -> None:
        """Make the GUI and the copies' colours show the sketch."""
        self.syncing = True
        try:
            for phase, rows in self.rows.items():
                priority = self.state.sketch.phase(phase).priority
                for mode, (status, slider) in rows.items():
                    status.value = self.state.status(phase, mode)
                    slider.visible = mode in priority
                    if mode in priority:
                        slider.value = float(priority[mode])
        finally:
            self.syncing = False
        with self.lock:
            if self.mesh is not None:
                self.mesh.batched_colors = self._colors()
