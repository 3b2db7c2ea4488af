"""A viewer cannot take Freeze away (issue 32): while the arm makes a long move, a viewer (no control) clicks
Replay 40 times on a two-hour recording. Before, those clicks filled viser's shared callback pool: the
operator's Freeze did nothing, the arm ran its whole move, and a new browser got no Freeze within 60 s.

Now the viewer's first click loads the recording and the other 39 are refused with a message (one slow job
per browser, kit/jobs.py); a new browser gets its Freeze at once; and the operator's Freeze, clicked in
Chromium, stops the arm within FREEZE_WITHIN_S (+ MARGIN_S for the measurement itself, see below).

The viewer and the newcomer are bare websockets (what a browser sends; a script clicks faster than a person);
the operator is Chromium, where the click is the point."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import viser
import zstandard
from playwright.sync_api import Browser, Page
from websockets.sync.client import ClientConnection, connect

from tests.support.big_recordings import write_long_recording
from tests.support.browser_pages import ARTIFACTS, open_tab, take_control
from tests.support.headless_viewer import CAMERA_HELLO, click_message, decode_window, notification
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant_ui as running_pendant

CLICKS = 40
FREEZE_WITHIN_S = 0.1  # the behaviour
# From the click as the page handled it (Playwright's mouse.up() returns then; the page sends the click from
# that handler): a stop is seen only at the next answer of GET /pose, polled on a machine shared with the
# loads: that is the margin. The time Chromium takes to hand the press to the page (software WebGL on a busy
# machine: some 300 ms here) is the browser's, not the pendant's, and is left out. Measured: docs/lan.md.
MARGIN_S = 0.3
NEW_BROWSER_FREEZE_S = 1.0  # the behaviour: from the websocket's opening to its Freeze button
PAGE_TIMEOUT_S = 60.0
MOVE_SPEED_PERCENT = 5.0
MOVE_J1_DEG = 140.0  # some 20 s at this speed: still moving when Freeze is clicked
STILL_TOL_DEG = 1e-6
STOP_WAIT_S = 10.0
RECORDING = "pendant-20260101-000000.mcap"
LOADING_S = 1.0  # the viewer's replay is loading (it takes some 6 s here) when the operator clicks


@pytest.fixture(scope="module")
def pendant(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Pendant]:
    data = tmp_path_factory.mktemp("data")
    (data / "recordings").mkdir()
    write_long_recording(data / "recordings" / RECORDING)  # two hours at 10 Hz
    with running_pendant(env={"PENDANT_DATA_DIR": str(data)}) as served:
        served.data = data
        yield served


def open_socket(pendant: Pendant) -> ClientConnection:
    """A browser's websocket to the page (viser's subprotocol, then its camera)."""
    ws = connect(
        f"ws://127.0.0.1:{pendant.ui_port}/",
        subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]  # websockets' Subprotocol is a str
        max_size=None,
        max_queue=None,
    )
    ws.send(CAMERA_HELLO)
    return ws


def read_until_button(ws: ClientConnection, label: str, seen: list[str]) -> str:
    """Read until a button labelled `label` comes; its uuid. Notifications read meanwhile go to `seen`."""
    zstd = zstandard.ZstdDecompressor()
    deadline = time.monotonic() + PAGE_TIMEOUT_S
    while time.monotonic() < deadline:
        frame = ws.recv(timeout=deadline - time.monotonic())
        assert isinstance(frame, bytes)
        for message in decode_window(frame, zstd):
            if (said := notification(message)) is not None:
                seen.append(said)
            if message.get("type") == "GuiButtonMessage" and message["props"].get("label") == label:
                return str(message["uuid"])
    raise AssertionError(f"no {label} button within {PAGE_TIMEOUT_S} s")


def read_notifications(ws: ClientConnection, seen: list[str], wanted: int, timeout_s: float) -> None:
    zstd = zstandard.ZstdDecompressor()
    deadline = time.monotonic() + timeout_s
    while len(seen) < wanted and time.monotonic() < deadline:
        try:
            frame = ws.recv(timeout=max(0.0, deadline - time.monotonic()))
        except TimeoutError:
            return
        assert isinstance(frame, bytes)
        seen.extend(said for m in decode_window(frame, zstd) if (said := notification(m)) is not None)


def stopped_after(pendant: Pendant, clicked_at: float) -> float:
    """Seconds from `clicked_at` to the first answer of GET /pose that the next one repeats (the arm
    stands still from there)."""
    last, last_at = None, None
    deadline = time.monotonic() + STOP_WAIT_S
    while time.monotonic() < deadline:
        pose = np.array(pendant.pose())
        now = time.monotonic()
        if last is not None and last_at is not None and np.allclose(pose, last, atol=STILL_TOL_DEG):
            return last_at - clicked_at
        last, last_at = pose, now
    raise AssertionError(f"the arm still moved {STOP_WAIT_S} s after Freeze")


@pytest.mark.measures  # a stop time from the click (FREEZE_WITHIN_S + MARGIN_S) on a real clock: run alone
def test_a_viewers_40_replays_leave_the_operators_freeze_working(browser: Browser, pendant: Pendant) -> None:
    operator: Page = browser.new_page(viewport={"width": 1400, "height": 900})
    try:
        freezes_the_arm_while_a_viewer_replays(operator, pendant)
    except BaseException:
        operator.screenshot(path=str(ARTIFACTS / "stop-path-40-replays-failed.png"))  # for whoever reads CI
        raise
    finally:
        operator.close()  # a rerun starts with a browser of its own


def freezes_the_arm_while_a_viewer_replays(operator: Page, pendant: Pendant) -> None:
    operator.goto(pendant.ui_url)
    freeze = operator.get_by_role("button", name="Freeze")
    freeze.wait_for(timeout=PAGE_TIMEOUT_S * 1000)
    # In control (on loopback the first page gets it; a loaded machine may say so late: then take it).
    take_control(operator)

    # Closed whatever happens: left open, it took control when the page closed, and its rerun never got it
    # (a clean-clone run: "this page never got control", after a first attempt that failed otherwise).
    viewer = open_socket(pendant)
    try:
        clicks_replays_while_the_operator_freezes(operator, pendant, viewer)
    finally:
        viewer.close()


def clicks_replays_while_the_operator_freezes(
    operator: Page, pendant: Pendant, viewer: ClientConnection
) -> None:
    told: list[str] = []
    replay = read_until_button(viewer, "Replay", told)
    pendant.api.put(
        "/recover"
    ).raise_for_status()  # a rerun finds the arm as the last attempt's Freeze left it
    start = pendant.pose()
    target = [start[0] + MOVE_J1_DEG, *start[1:]]
    pendant.api.put("/pose", params={"speed": MOVE_SPEED_PERCENT}, json={"angles": target}).raise_for_status()

    for _ in range(CLICKS):
        viewer.send(click_message(replay))
    time.sleep(LOADING_S)

    newcomer = open_socket(pendant)
    try:
        opened = time.monotonic()
        read_until_button(newcomer, "Freeze", [])
        waited = time.monotonic() - opened
    finally:
        newcomer.close()
    assert waited < NEW_BROWSER_FREEZE_S, f"a new browser waited {waited:.2f} s for its Freeze button"

    moving = pendant.pose()
    freeze = operator.get_by_role("button", name="Freeze")
    assert not np.allclose(moving, start, atol=1.0) and not np.allclose(moving, target, atol=1.0), moving
    freeze.hover()  # Playwright's checks that the button can be clicked, before the clock starts
    pressed_at = time.monotonic()
    operator.mouse.down()
    operator.mouse.up()  # returns once Chromium's page has handled the click, which sends it
    clicked_at = time.monotonic()
    took = stopped_after(pendant, clicked_at)
    assert took < FREEZE_WITHIN_S + MARGIN_S, (
        f"the arm stopped {took * 1000:.0f} ms after the click ({(clicked_at - pressed_at) * 1000:.0f} ms "
        "from the mouse's press to the page's click before that)"
    )
    assert not np.allclose(pendant.pose(), target, atol=1.0), "the arm ran its whole move"

    read_notifications(viewer, told, CLICKS - 1, PAGE_TIMEOUT_S)
    refused = [said for said in told if said.startswith("Replay refused")]
    assert len(refused) == CLICKS - 1, told
    assert "Replay is still running in this browser" in refused[0]


def test_a_recording_sent_in_parts_downloads_whole_in_chromium(
    browser: Browser, pendant: Pendant, tmp_path: Path
) -> None:
    """The parts are read from disk as the browser takes them (kit/download.py): Chromium saves the file."""
    page = browser.new_page(viewport={"width": 1400, "height": 900}, accept_downloads=True)
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=PAGE_TIMEOUT_S * 1000)
    open_tab(page, "Dashboard")  # once the whole panel is there (a click before stayed on the Jog tab)
    with page.expect_download(timeout=PAGE_TIMEOUT_S * 1000) as download:
        page.get_by_role("button", name="Download MCAP").click()
    saved = tmp_path / download.value.suggested_filename
    download.value.save_as(saved)
    page.close()
    assert saved.name == RECORDING
    assert saved.read_bytes() == (pendant.data / "recordings" / RECORDING).read_bytes()
