"""A real pendant process (simulator + UI + API on loopback) and a real Chromium driven by Playwright."""

from __future__ import annotations

import contextlib
import os
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.api.server import answers, free_port, wait_until

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"
START_TIMEOUT_S = 60.0


class Pendant:
    def __init__(self, ui_port: int, api_port: int) -> None:
        self.ui_port = ui_port
        self.ui_url = f"http://127.0.0.1:{ui_port}/"
        self.api = httpx.Client(base_url=f"http://127.0.0.1:{api_port}", timeout=5.0)

    def pose(self) -> list[float]:
        return self.api.get("/pose").json()["angles"]

    def status(self) -> str:
        return self.api.get("/status/motion").text.strip('"')


@contextlib.contextmanager
def running_pendant(*flags: str, env: dict[str, str] | None = None) -> Iterator[Pendant]:
    """A `pendant` process (simulator, UI and API on free loopback ports) with extra `flags`."""
    ui_port, api_port = free_port(), free_port()
    data = tempfile.TemporaryDirectory(prefix="pendant-data-")  # its event log and recordings
    process = subprocess.Popen(
        [sys.executable, "-m", "pendant", "--ui-port", str(ui_port), "--api-port", str(api_port), *flags],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        env={**os.environ, "PYTHONUNBUFFERED": "1", "PENDANT_DATA_DIR": data.name, **(env or {})},
    )
    try:
        wait_until(lambda: answers(f"http://127.0.0.1:{api_port}/pose"), START_TIMEOUT_S, "the API")
        wait_until(lambda: answers(f"http://127.0.0.1:{ui_port}/"), START_TIMEOUT_S, "the page")
        yield Pendant(ui_port, api_port)
    finally:
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10)
        data.cleanup()


@pytest.fixture(scope="module")
def pendant() -> Iterator[Pendant]:
    with running_pendant() as served:
        yield served


@pytest.fixture(scope="module")
def browser() -> Iterator[object]:
    from playwright.sync_api import sync_playwright

    if not Path(CHROMIUM).exists():
        pytest.fail(f"Chromium not found at {CHROMIUM}: install Debian's chromium (apt-get install chromium)")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield browser
        browser.close()


@pytest.fixture
def page(browser, pendant: Pendant):  # type: ignore[no-untyped-def]
    ARTIFACTS.mkdir(exist_ok=True)
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=30_000)
    yield page
    page.close()
