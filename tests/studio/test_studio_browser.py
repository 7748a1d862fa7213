"""The studio in a real headless Chromium: palette, marking modes, live sketch, sandbox,
optimization, playback."""

import http.server
import re
import threading
import time

import numpy as np
import pytest

from studio_helpers import gui_label, save_doc_image

pytestmark = pytest.mark.browser


def wait_until(predicate, timeout: float = 20.0, what: str = "condition"):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"timed out waiting for {what}")


def row(page, label: str):
    """The GUI row (label + control) whose label reads exactly `label`."""
    return page.locator(
        f"xpath=//label[normalize-space(.)='{label}']/ancestor::div[contains(@class,'mantine-Flex-root')][1]"
    )


def choose(page, label: str, option: str) -> None:
    page.get_by_label(label).click()
    page.get_by_role("option", name=option, exact=True).click()


def expand(page, folder_title: str) -> None:
    page.get_by_text(folder_title, exact=True).click()


def screenshot(page, artifacts, name: str):
    page.add_style_tag(content=".mantine-Notification-root { display: none !important; }")
    page.wait_for_timeout(300)
    path = artifacts / name
    page.screenshot(path=path)
    return path


def status_text(page) -> str:
    return page.get_by_text(
        re.compile(r"^(Ready\.|Refused:|Loaded|Saved|Kept|Wrote|Playing|Optimiz|Resuming)")
    ).first.inner_text()


def copy_color(studio, phase: str, mode: int) -> np.ndarray:
    palette = studio.palette
    geoms = len(palette.geom_shade) // len(palette.copies)
    return np.asarray(palette.mesh.batched_colors)[
        palette.copies.index((phase, mode)) * geoms
    ].astype(int)


def test_palette_lists_every_mode_of_both_phases(studio, page, artifacts):
    expand(page, "Ground modes (30)")
    labels = page.locator("label").all_inner_texts()
    for phase in ("air", "ground"):
        shown = [
            t for t in labels if re.fullmatch(rf"{phase} \d+ · [\d.]+ Hz", t.replace("\u200b", ""))
        ]
        assert len(shown) == studio.state.modes(phase).count == 30
        numbers = [int(t.split()[1]) for t in shown]
        assert numbers == list(range(1, 31))
        hz = [float(t.split("·")[1].split()[0]) for t in shown]
        assert hz == sorted(hz), "modes are listed in frequency order"
    assert len(studio.palette.copies) == 60
    positions = np.asarray(studio.palette.mesh.batched_positions).copy()
    wait_until(
        lambda: not np.allclose(positions, studio.palette.mesh.batched_positions),
        timeout=10,
        what="the palette copies to vibrate",
    )
    expand(page, "Ground modes (30)")
    # software WebGL: keep the page responsive for the rest
    page.get_by_label("animate palette").uncheck()
    wait_until(lambda: not studio.palette.animate.value, what="the palette to pause")


def test_selecting_a_mode_marks_it_in_gui_scene_and_sketch_file(studio, page, artifacts):
    label = gui_label(studio, "air", 3)
    assert page.get_by_label(label).input_value() == "allowed"
    choose(page, label, "priority")
    wait_until(lambda: studio.state.status("air", 3) == "priority", what="air 3 to become priority")
    wait_until(
        lambda: (c := copy_color(studio, "air", 3))[1] > c[0] + 60, what="the copy to turn green"
    )
    row(page, "ψ air 3 (N·m)").wait_for()
    choose(page, gui_label(studio, "air", 5), "excluded")
    wait_until(
        lambda: (c := copy_color(studio, "air", 5))[0] > c[1] + 60, what="the copy to turn red"
    )
    saved = studio.state.autosave_path.read_text()
    assert "priority:\n    '3': 20.0" in saved and "- 5" in saved.split("excluded:")[1]
    expand(page, "Ground modes (30)")
    choose(page, gui_label(studio, "ground", 2), "priority")
    wait_until(lambda: studio.state.status("ground", 2) == "priority", what="ground 2 priority")
    expand(page, "Ground modes (30)")
    save_doc_image(screenshot(page, artifacts, "palette.png"), "studio_palette.png")


def test_moving_a_slider_changes_the_sketch_motion(studio, page, artifacts):
    if studio.state.status("air", 3) != "priority":
        choose(page, gui_label(studio, "air", 3), "priority")
    wait_until(
        lambda: studio.sketch_view.latency_s == studio.sketch_view.latency_s, what="a first sketch"
    )
    time.sleep(0.5)
    shown, before = studio.stage.shown, studio.stage.positions.copy()
    start = time.perf_counter()
    row(page, "ψ air 3 (N·m)").get_by_role("slider").press("End")
    wait_until(lambda: studio.stage.shown > shown, timeout=10, what="a new sketch on stage")
    latency = time.perf_counter() - start
    assert studio.state.sketch.air.priority[3] == 200.0
    after = studio.stage.positions
    span = min(len(before), len(after))
    assert np.abs(after[:span] - before[:span]).max() > 0.01, (
        "a larger activation moves the character more"
    )
    assert latency < 3.0
    print(
        f"slider → new sketch on stage: {latency * 1000:.0f} ms "
        f"(server-side {studio.sketch_view.latency_s * 1000:.0f} ms)"
    )
    save_doc_image(screenshot(page, artifacts, "sketch.png"), "studio_sketch.png")


def test_a_second_tab_sees_the_same_sketch(studio, browser, page):
    choose(page, gui_label(studio, "air", 4), "excluded")
    wait_until(lambda: studio.state.status("air", 4) == "excluded", what="air 4 excluded")
    other = browser.new_page(viewport={"width": 1400, "height": 900})
    try:
        other.goto(studio.url)
        other.get_by_label(gui_label(studio, "air", 4)).wait_for(timeout=30_000)
        assert other.get_by_label(gui_label(studio, "air", 4)).input_value() == "excluded"
        choose(other, gui_label(studio, "air", 4), "allowed")
        wait_until(
            lambda: page.get_by_label(gui_label(studio, "air", 4)).input_value() == "allowed",
            what="the first tab to follow the second",
        )
    finally:
        other.close()


@pytest.mark.parametrize("outside", ["../x.xml", "/etc/passwd", "../../etc/hosts.yaml"])
def test_paths_outside_the_studio_folder_are_refused(studio, page, outside):
    character_before = studio.state.sketch.character
    row(page, "file").locator("input").fill(outside)
    page.get_by_role("button", name="Load file").click()
    wait_until(
        lambda: "outside the studio folder" in status_text(page), what="a refusal in the page"
    )
    assert status_text(page).startswith("Refused:")
    assert studio.state.sketch.character == character_before


def test_without_the_token_the_studio_refuses_the_page(studio, browser):
    stranger = browser.new_page()
    try:
        response = stranger.goto(studio.url.split("?")[0])
        assert response.status == 403 and "Forbidden" in stranger.content()
        assert stranger.goto(studio.url.replace("token=", "token=x")).status == 403
    finally:
        stranger.close()


OPEN_WEBSOCKET = """([url, protocol]) => new Promise(done => {
    const ws = new WebSocket(url, [protocol]);
    ws.onopen = () => { ws.close(); done("open"); };
    ws.onerror = () => done("refused");
})"""


@pytest.fixture
def elsewhere():
    """Another site on this machine: an empty page at http://127.0.0.1:PORT/."""

    class Blank(http.server.BaseHTTPRequestHandler):
        def do_GET(self):
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.end_headers()
            self.wfile.write(b"<html><body>elsewhere</body></html>")

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Blank)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{server.server_address[1]}/"
    server.shutdown()


def test_a_page_from_another_origin_cannot_open_the_websocket(studio, browser, page, elsewhere):
    """The browser holds the token's cookie, sent along to the same site: only the Origin check
    stands in the way."""
    import viser

    port = studio.server.get_port()
    target = [f"ws://127.0.0.1:{port}", f"viser-v{viser.__version__}"]
    assert page.evaluate(OPEN_WEBSOCKET, target) == "open"
    context = browser.new_context()
    try:
        context.add_cookies(
            [
                {
                    "name": studio.gate.cookie,
                    "value": studio.gate.token,
                    "url": f"http://127.0.0.1:{port}/",
                    "httpOnly": True,
                    "sameSite": "Strict",
                }
            ]
        )
        foreign = context.new_page()
        foreign.goto(elsewhere)
        assert foreign.evaluate(OPEN_WEBSOCKET, target) == "refused"
    finally:
        context.close()


def test_saving_over_an_existing_file_asks_first(studio, page):
    name = row(page, "save sketch as").locator("input")
    name.fill("asked.sketch.yaml")
    name.press("Tab")
    wait_until(
        lambda: studio.character_panel.save_name.value == "asked.sketch.yaml", what="the file name"
    )
    path = studio.sandbox.root / "asked.sketch.yaml"
    page.get_by_role("button", name="Save sketch").click()
    wait_until(path.is_file, what="the first save")
    first = path.read_text()
    choose(page, gui_label(studio, "air", 6), "excluded")
    wait_until(lambda: studio.state.status("air", 6) == "excluded", what="air 6 excluded")
    page.get_by_role("button", name="Save sketch").click()
    page.get_by_role("button", name="Keep the file").click()
    wait_until(lambda: status_text(page).startswith("Kept"), what="the file to be kept")
    assert path.read_text() == first
    page.get_by_role("button", name="Save sketch").click()
    page.get_by_role("button", name="Overwrite").click()
    wait_until(lambda: path.read_text() != first, what="the file to be replaced")
    assert studio.state.status("air", 6) == "excluded"


def test_optimization_runs_in_the_background_and_its_plot_advances(studio, page, artifacts):
    expand(page, "Optimize (gravity on)")
    number = row(page, "max evaluations").locator("input")
    number.fill("120")
    number.press("Tab")
    wait_until(lambda: studio.optimize_panel.budget.value == 120, what="the budget")
    page.get_by_role("button", name="Start new run").click()
    progress = page.get_by_text(re.compile(r"^studio-runs/run-.*generation \d+"))
    progress.wait_for(timeout=30_000)
    first = int(re.search(r"generation (\d+)", progress.inner_text()).group(1))
    # the page stays responsive during the run
    page.get_by_label(gui_label(studio, "air", 1)).click()
    page.keyboard.press("Escape")
    wait_until(
        lambda: int(re.search(r"generation (\d+)", progress.inner_text()).group(1)) > first,
        timeout=40,
        what="the plot to advance",
    )
    assert page.locator(".uplot canvas").count() >= 2
    wait_until(lambda: not studio.optimize_panel.running, timeout=60, what="the run to finish")
    assert (studio.optimize_panel.folder / "best_controller.json").is_file()
    page.mouse.move(5, 5)
    expand(page, "Air modes (30)")
    page.locator(".uplot").last.scroll_into_view_if_needed()
    save_doc_image(screenshot(page, artifacts, "optimize.png"), "studio_optimize.png")
    expand(page, "Play (gravity on)")
    page.get_by_role("button", name="Play best gait so far").click()
    page.get_by_text(re.compile(r"m/s forward")).wait_for(timeout=30_000)
    assert studio.stage.showing == "playback" and studio.stage.follow
    page.get_by_role("button", name="Export BVH").click()
    wait_until(lambda: (studio.sandbox.root / "gait.bvh").is_file(), what="the BVH file")
    screenshot(page, artifacts, "playback.png")


def test_a_mocap_clip_is_tracked_from_the_page(studio, page, artifacts):
    from conftest import MOCAP_WALK

    # the page's flow is under test, not the tracker: the walk's first 1.25 s (150 frames) do
    lines = MOCAP_WALK.read_text().splitlines()
    count = lines.index("MOTION") + 1
    lines[count] = "Frames: 150"
    (studio.sandbox.root / "walk.bvh").write_text("\n".join(lines[: count + 2 + 150]) + "\n")
    expand(page, "Track mocap (gravity on)")
    clip = row(page, "BVH clip").locator("input")
    clip.fill("walk.bvh")
    clip.press("Tab")
    wait_until(lambda: studio.track_panel.clip.value == "walk.bvh", what="the clip name")
    page.get_by_role("button", name="Track in physics").click()
    page.get_by_text(re.compile(r"joint RMS")).wait_for(timeout=180_000)
    assert studio.stage.showing == "tracking" and studio.stage.follow
    result = studio.track_panel.result
    assert not result.fell and result.duration_s > 1.2  # the walk at robustness 0.5, in full
    screenshot(page, artifacts, "tracking.png")
