"""Optimize the current sketch from the page: start, stop, resume, a live plot, play the best gait
so far.

The optimization is the CLI's own (`python -m eigengait optimize SKETCH -o FOLDER
…`) run in a child process, so the page never waits on it and Stop simply ends the process; every
generation is checkpointed, so Resume continues it (`--resume`). Runs go to
`studio-runs/run-YYYYmmdd-HHMMSS/` in the studio folder; the plots follow the run's `log.csv`
(log₁₀ of the best objective and best cycle violation per generation).
"""

from __future__ import annotations

import csv
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from datetime import datetime
from pathlib import Path

import numpy as np
import viser
import viser.uplot as uplot

from eigengait.errors import UserInputError
from eigengait.optimize.staged import STAGE_ONE
from eigengait.studio.messages import Messages
from eigengait.studio.state import StudioState

RUNS_FOLDER = "studio-runs"
POLL_SECONDS = 0.5
CHILD_LOG = "studio-optimize.log"


def read_log(path: Path) -> dict[str, np.ndarray]:
    """Columns of a run's log.csv as float arrays (empty when there is no log yet)."""
    if not path.is_file():
        return {}
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return {}
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


class OptimizePanel:
    def __init__(
        self,
        server: viser.ViserServer,
        state: StudioState,
        messages: Messages,
        play: Callable[[Path, viser.ClientHandle | None], None],
        gui_order: float,
    ):
        self.server, self.state, self.messages, self.play = server, state, messages, play
        self.process: subprocess.Popen | None = None
        self.folder: Path | None = None
        self.generations = 0
        gui = server.gui
        with gui.add_folder("Optimize (gravity on)", order=gui_order, expand_by_default=False):
            self.budget = gui.add_number("max evaluations", 2000, min=50, step=50)
            self.start = gui.add_button("Start new run", icon=viser.Icon.PLAYER_PLAY)
            self.stop = gui.add_button("Stop", icon=viser.Icon.PLAYER_STOP, disabled=True)
            self.resume = gui.add_button(
                "Resume last run", icon=viser.Icon.PLAYER_TRACK_NEXT, disabled=True
            )
            self.progress = gui.add_markdown("No run yet.")
            self.cost_plot = self._plot("log₁₀ best objective f", "#2a6fb0")
            self.violation_plot = self._plot("log₁₀ cycle violation max|φᵢ|", "#c0392b")
            self.play_best = gui.add_button(
                "Play best gait so far", icon=viser.Icon.WALK, disabled=True
            )
        self.start.on_click(messages.guarded(self._on_start))
        self.stop.on_click(messages.guarded(self._on_stop))
        self.resume.on_click(messages.guarded(self._on_resume))
        self.play_best.on_click(messages.guarded(self._on_play_best))
        threading.Thread(target=self._poll, name="optimize-poll", daemon=True).start()

    def _plot(self, title: str, color: str) -> viser.GuiUplotHandle:
        """A chart hidden until the first generation (viser's uPlot does not draw data given to an
        empty chart)."""
        placeholder = np.array([0.0, 1.0])
        return self.server.gui.add_uplot(
            (placeholder, np.zeros(2)),
            (uplot.Series(label="generation"), uplot.Series(label=title, stroke=color, width=2)),
            title=title,
            scales={"x": uplot.Scale(time=False, auto=True), "y": uplot.Scale(auto=True)},
            legend=uplot.Legend(show=False),
            aspect=2.0,
            visible=False,
        )

    def _launch(self, folder: Path, resume: bool) -> None:
        if self.running:
            raise UserInputError("an optimization is already running", fix="stop it first")
        sketch = self.state.autosave_path
        self.state.autosave()
        folder.mkdir(parents=True, exist_ok=True)
        command = [
            sys.executable,
            "-m",
            "eigengait",
            "optimize",
            str(sketch),
            "-o",
            str(folder),
            "--max-evaluations",
            str(int(self.budget.value)),
            *(["--resume"] if resume else []),
        ]
        log = open(folder / CHILD_LOG, "a")
        self.process = subprocess.Popen(
            command,
            cwd=self.state.sandbox.root,
            stdout=log,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
        )
        log.close()
        self.folder = folder
        self._buttons()

    @property
    def running(self) -> bool:
        return self.process is not None and self.process.poll() is None

    def _on_start(self, event: viser.GuiEvent) -> None:
        folder = (
            self.state.sandbox.root / RUNS_FOLDER / datetime.now().strftime("run-%Y%m%d-%H%M%S")
        )
        self._launch(folder, resume=False)
        self.messages.info(f"Optimizing in `{self.state.sandbox.relative(folder)}`.", event.client)

    def _on_stop(self, event: viser.GuiEvent) -> None:
        if self.running:
            self.process.terminate()
            self.process.wait(timeout=30)
        self._buttons()
        self.messages.info(
            "Optimization stopped; Resume continues from the last generation.", event.client
        )

    def _on_resume(self, event: viser.GuiEvent) -> None:
        if self.folder is None or not (self.folder / "checkpoint.npz").is_file():
            raise UserInputError("nothing to resume yet: no generation has been checkpointed")
        self._launch(self.folder, resume=True)
        self.messages.info(f"Resuming `{self.state.sandbox.relative(self.folder)}`.", event.client)

    def _on_play_best(self, event: viser.GuiEvent) -> None:
        path = self.folder / "best_controller.json" if self.folder else None
        if path is None or not path.is_file():
            raise UserInputError(
                "no best controller yet", fix="wait for the first generation to finish"
            )
        self.play(path, event.client)

    def _buttons(self) -> None:
        running = self.running
        self.start.disabled = running
        self.stop.disabled = not running
        self.resume.disabled = running or self.folder is None
        self.play_best.disabled = (
            self.folder is None or not (self.folder / "best_controller.json").is_file()
        )

    def _poll(self) -> None:
        was_running = False
        while True:
            time.sleep(POLL_SECONDS)
            if self.folder is None:
                continue
            try:
                self._refresh(was_running)
            except (OSError, ValueError, KeyError):
                continue  # the log is being replaced; read it next time
            was_running = self.running

    def _refresh(self, was_running: bool) -> None:
        # the open-loop stage logs in its own folder
        stage_one = self.folder / STAGE_ONE / "log.csv"
        log = read_log(
            self.folder / "log.csv" if (self.folder / "log.csv").is_file() else stage_one
        )
        if log and len(log["generation"]) != self.generations:
            self.generations = len(log["generation"])
            g = log["generation"]
            self.cost_plot.data = (g, np.log10(np.maximum(log["best_cost"], 1e-12)))
            self.violation_plot.data = (g, np.log10(np.maximum(log["best_violation"], 1e-12)))
            self.cost_plot.visible = self.violation_plot.visible = True
            self.progress.content = (
                f"`{self.state.sandbox.relative(self.folder)}` · generation {int(g[-1])} · "
                f"{int(log['evaluations'][-1])} evaluations · {log['seconds'][-1]:.0f} s · best f "
                f"{log['best_cost'][-1]:.4g} · violation {log['best_violation'][-1]:.3g}"
            )
            self._buttons()
        if was_running and not self.running:
            code = self.process.returncode
            if code == 0:
                self.messages.info(f"Optimization finished after {self.generations} generations.")
            elif code > 0:
                tail = (self.folder / CHILD_LOG).read_text().strip().splitlines()[-1:] or [
                    "(no output)"
                ]
                self.messages.error(f"the optimization ended with status {code}: {tail[0]}")
            self._buttons()

    def close(self) -> None:
        if self.running:
            self.process.terminate()
            self.process.wait(timeout=30)
