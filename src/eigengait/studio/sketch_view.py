"""The live sketch: the current pulse controller simulated with gravity off, replayed on the stage
at real time.

Any change to the sketch (a status, a ψ slider, a timing value, the character) wakes a worker
thread; it waits DEBOUNCE_SECONDS for the edits to settle, simulates SKETCH_CYCLES cycles with the
system built once per character and pose, and swaps the new frames in. The panel reports the latency
from the last edit to the new motion on screen.
"""

from __future__ import annotations

import threading
import time

import viser

from eigengait.control.sketch_sim import simulate_sketch
from eigengait.studio.messages import Messages
from eigengait.studio.stage import Stage
from eigengait.studio.state import StudioState

DEBOUNCE_SECONDS = 0.12
SKETCH_CYCLES = 3
TIMING_FIELDS = (
    ("period", "period T (s)", 0.2, 2.0, 0.01),
    ("air_ratio", "air ratio α", 0.05, 0.95, 0.01),
    ("pulse_air", "air pulse δa (s)", 0.01, 0.5, 0.005),
    ("pulse_ground", "ground pulse δc (s)", 0.01, 0.5, 0.005),
)


class SketchView:
    def __init__(
        self,
        server: viser.ViserServer,
        state: StudioState,
        stage: Stage,
        messages: Messages,
        gui_order: float,
    ):
        self.server, self.state, self.stage, self.messages = server, state, stage, messages
        self.wake = threading.Event()
        self.edited_at = 0.0
        self.latency_s = float("nan")
        self.syncing = False
        with server.gui.add_folder("Sketch (gravity off)", order=gui_order):
            self.sliders = {
                field: self._timing_slider(field, *spec) for field, *spec in TIMING_FIELDS
            }
            self.report = server.gui.add_markdown("")
            self.replay = server.gui.add_button("Show sketch on stage", icon=viser.Icon.PLAYER_PLAY)
        self.replay.on_click(lambda _: self._request())
        state.subscribe("sketch", self._request)
        threading.Thread(target=self._work, name="sketch-simulation", daemon=True).start()

    def _timing_slider(self, field: str, label: str, low: float, high: float, step: float):
        slider = self.server.gui.add_slider(label, low, high, step, low)

        @slider.on_update
        @self.messages.guarded
        def _(event: viser.GuiEvent) -> None:
            if not self.syncing:
                self.state.set_timing(**{field: slider.value})

        return slider

    def _request(self) -> None:
        self.edited_at = time.perf_counter()
        self._sync_sliders()
        self.wake.set()

    def _sync_sliders(self) -> None:
        self.syncing = True
        try:
            for field, slider in self.sliders.items():
                slider.value = float(getattr(self.state.sketch.timing, field))
        finally:
            self.syncing = False

    def _work(self) -> None:
        while True:
            self.wake.wait()
            time.sleep(DEBOUNCE_SECONDS)
            self.wake.clear()
            try:
                self._simulate()
            except Exception as exc:  # a sketch that cannot be simulated must not stop the worker
                self.messages.error(f"the sketch could not be simulated: {exc}")

    def _simulate(self) -> None:
        with self.state.lock:
            edited = self.edited_at
            sketch, system = self.state.sketch, self.state.system
            seconds = SKETCH_CYCLES * sketch.timing.period
            run = simulate_sketch(sketch, seconds, system=system)
        self.stage.show("sketch", run.world, run.qpos, run.fps)
        self.latency_s = time.perf_counter() - edited
        priority = {ph: len(sketch.phase(ph).priority) for ph in ("air", "ground")}
        self.report.content = (
            f"{priority['air']} air + {priority['ground']} ground priority modes · {seconds:.2f} s "
            f"simulated in {run.wall_seconds * 1000:.0f} ms "
            f"({seconds / max(run.wall_seconds, 1e-9):.0f}× real time) · largest joint rotation "
            f"{run.max_joint_rotation_deg:.0f}° · on stage "
            f"{self.latency_s * 1000:.0f} ms after the edit"
        )
