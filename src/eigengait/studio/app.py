"""The eigengait studio: a viser server with the palette, the live sketch, optimization and
playback.

One `Studio` holds one shared state; every browser tab sees and edits the same sketch (viser GUI
handles are server-wide). An animation thread pushes the palette's and the stage's frames at
ANIMATION_FPS. Only the studio's own page, opened with the printed address and its token, gets
through (`access.py`).
"""

from __future__ import annotations

import contextlib
import io
import threading
import time
from pathlib import Path

import viser

from eigengait.render.offscreen import use_offscreen_gl
from eigengait.studio.access import AccessGate, guarded_serving
from eigengait.studio.character_panel import CharacterPanel
from eigengait.studio.messages import Messages
from eigengait.studio.listen import check_listen_address, port_taken
from eigengait.studio.optimize_panel import OptimizePanel
from eigengait.studio.palette_view import PaletteView
from eigengait.studio.play_panel import PlayPanel
from eigengait.studio.track_panel import TrackPanel
from eigengait.studio.sandbox import Sandbox
from eigengait.studio.sketch_view import SketchView
from eigengait.studio.stage import Stage
from eigengait.studio.state import StudioState

ANIMATION_FPS = 25.0
CAMERA_POSITION = (5.2, -0.3, 2.2)  # m: front-right of the stage, the palette walls behind it
CAMERA_LOOK_AT = (-2.5, 0.9, 1.3)


class Studio:
    def __init__(
        self,
        root: str | Path = ".",
        target: str | None = None,
        host: str = "127.0.0.1",
        port: int = 8080,
    ):
        use_offscreen_gl()  # the videos the studio exports render offscreen, without a display
        self.sandbox = Sandbox(root)
        self.state = StudioState(self.sandbox)
        self.gate = AccessGate(host, port)
        self.server = start_server(self.gate, host, port)
        self.server.scene.set_up_direction("+z")
        self.server.scene.configure_environment_map(None)  # plain lights: far cheaper without a GPU
        self.server.scene.configure_default_lights(True, cast_shadow=False)
        self.server.scene.add_light_hemisphere(
            "/lights/sky", ground_color=(150, 150, 150), intensity=1.4
        )
        self.server.gui.configure_theme(
            control_width="large", show_logo=False, show_share_button=False
        )
        self.server.gui.add_markdown(
            "**eigengait studio** — mode numbers start at 1 (lowest non-rigid mode); ψ in N·m.",
            order=0.0,
        )
        self.messages = Messages(self.server)
        self.stage = Stage(self.server)
        self.character_panel = CharacterPanel(self.server, self.state, self.messages, gui_order=1.0)
        self.sketch_view = SketchView(
            self.server, self.state, self.stage, self.messages, gui_order=2.0
        )
        self.palette = PaletteView(self.server, self.state, self.messages, gui_order=3.0)
        self.play_panel = PlayPanel(
            self.server, self.sandbox, self.stage, self.messages, gui_order=5.0
        )
        self.track_panel = TrackPanel(
            self.server, self.sandbox, self.stage, self.messages, gui_order=6.0
        )
        self.optimize_panel = OptimizePanel(
            self.server, self.state, self.messages, self.play_panel.play_file, gui_order=4.0
        )
        self.server.on_client_connect(self._frame_camera)
        self.state.open(target)
        self.frames_sent = 0
        self.running = True
        self.animation = threading.Thread(
            target=self._animate, name="studio-animation", daemon=True
        )
        self.animation.start()

    @property
    def url(self) -> str:
        """The address to open: the studio's page with its access token."""
        host = "127.0.0.1" if self.gate.all_interfaces else self.server.get_host()
        host = f"[{host}]" if ":" in host else host
        return f"http://{host}:{self.server.get_port()}/?token={self.gate.token}"

    def _frame_camera(self, client: viser.ClientHandle) -> None:
        with client.atomic():
            client.camera.up_direction = (0.0, 0.0, 1.0)
            client.camera.position = CAMERA_POSITION
            client.camera.look_at = CAMERA_LOOK_AT

    def _animate(self) -> None:
        period = 1.0 / ANIMATION_FPS
        next_frame = time.perf_counter()
        while self.running:
            now = time.perf_counter()
            with self.server.atomic():
                self.palette.tick(now)
                self.stage.tick(now)
            self.frames_sent += 1
            next_frame = max(next_frame + period, now)
            time.sleep(max(0.0, next_frame - time.perf_counter()))

    def stop(self) -> None:
        self.running = False
        self.optimize_panel.close()
        self.server.stop()


def start_server(gate: AccessGate, host: str, port: int) -> viser.ViserServer:
    """A viser server on exactly `port` whose every HTTP request and WebSocket handshake passes the
    gate first (viser's own banner, which gives the address without the token, is not shown)."""
    with guarded_serving(gate) as ports, contextlib.redirect_stdout(io.StringIO()):
        server = viser.ViserServer(host=host, port=port, label="eigengait studio", verbose=False)
    if ports and server.get_port() == port:
        return server
    server.stop()
    if not ports:
        raise RuntimeError(
            "viser did not start its server through websockets.asyncio.server.serve: the studio "
            "cannot check who connects, so it does not run"
        )
    raise port_taken(host, port)  # taken since the check: viser moved on to another port


def main(
    target: str | None = None, host: str = "127.0.0.1", port: int = 8080, root: str | Path = "."
) -> None:
    """Run the studio until interrupted, serving files from `root` only."""
    check_listen_address(host, port)
    studio = Studio(root, target, host, port)
    print(
        f"eigengait studio: {studio.url}  (folder {studio.sandbox.root}; Ctrl+C to stop)",
        flush=True,
    )
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        pass
    finally:
        studio.stop()
