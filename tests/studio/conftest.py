"""A studio served from a temporary folder and a headless Debian Chromium driven by Playwright."""

import os
import socket

import pytest
from studio_helpers import ARTIFACTS, gui_label
from shared_data import MOCAP

CHROMIUM = "/usr/bin/chromium"
MOCAP_WALK = MOCAP / "cmu_02_01_walk.bvh"
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def studio(tmp_path_factory):
    from eigengait.studio.app import Studio

    root = tmp_path_factory.mktemp("studio-folder")
    app = Studio(root, "humanoid", port=free_port())
    yield app
    app.stop()


@pytest.fixture(scope="module")
def browser():
    if not os.path.exists(CHROMIUM):
        pytest.skip(
            "Debian chromium is not installed (scripts/install-system-deps.sh --with-browser)"
        )
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def page(studio, browser):
    """One tab on the studio, palette loaded, the software-WebGL notice dismissed."""
    tab = browser.new_page(viewport={"width": 1440, "height": 900})
    tab.goto(studio.url)
    tab.get_by_label(gui_label(studio, "air", 1)).wait_for(timeout=30_000)
    yield tab
    tab.close()


@pytest.fixture(scope="session")
def artifacts():
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    return ARTIFACTS
