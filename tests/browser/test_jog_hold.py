"""Jogging in a real Chromium (software WebGL), measured as the operator feels it: the arm's pose sampled over
the API while the page holds a jog button by mouse or finger, against the same motion sent to the API.

Bounds are generous and physical (the machine is shared, so the timing targets live in benchmarks/jog.py):
a held button delivers most of the API-sent motion without a stop inside the press, the arm is still soon
after the release, a swipe that starts on a jog button never moves the arm. (Freeze on screen in every
tab at every scroll position: test_screen_fit.py.)
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Iterator

import pytest
from playwright.sync_api import Browser, FloatRect, Page

from tests.support.browser_pages import ARTIFACTS
from tests.support.jog_measure import (
    PoseSampler,
    api_hold,
    button_box,
    button_centre,
    close_while_held,
    ensure_operator,
    hang_main_thread,
    key_hold,
    mouse_hold,
    on_top,
    open_as_operator,
    pose_changes,
    settled,
    touch_hold,
    touch_swipe,
    wait_idle,
    wait_settled,
)
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant_ui as running_pendant

HOLD_S = 1.0
PRESSES = 3
# Of the API-sent motion, median over the presses. The target is 90 % (benchmarks/jog.py measures it); the
# test asserts what tells a smooth hold from the old stutter (4-36 %) with room for a loaded CI machine.
MIN_SHARE = 0.7
# Released: the arm stops within this, well inside the 3 s a continuous jog plans ahead (so it was the
# release that stopped it, not the end of the plan). The p99 on a quiet machine is in README/benchmarks.
STOP_WITHIN_S = 1.5
STILL_AFTER_S = 0.5
STILL_TOL_DEG = 0.01
DESKTOP, TABLET_LANDSCAPE, TABLET_PORTRAIT = (1400, 900), (1024, 768), (768, 1024)


@pytest.fixture
def touch_page(browser: Browser, pendant: Pendant) -> Iterator[Page]:
    page = browser.new_page(viewport={"width": 1024, "height": 768}, has_touch=True)
    open_as_operator(page, pendant.ui_url)
    yield page
    page.close()


def still_after(pendant: Pendant) -> None:
    first = pendant.pose()
    time.sleep(STILL_AFTER_S)
    assert max(abs(a - b) for a, b in zip(pendant.pose(), first, strict=True)) < STILL_TOL_DEG


@pytest.mark.measures  # a share of the API's motion, a stop time
def test_holding_j1_by_mouse_moves_it_as_far_as_the_api_and_stops_on_release(
    page: Page, pendant: Pendant
) -> None:
    ensure_operator(page)
    wait_settled(page)  # the page's first frames (shaders built) take the machine for a moment
    api = [api_hold(pendant.api, HOLD_S, +1 if i % 2 == 0 else -1).moved_deg for i in range(PRESSES)]
    held, stalls = [], 0
    for i in range(PRESSES):
        timeline = mouse_hold(page, pendant.api, "J1+" if i % 2 == 0 else "J1-", HOLD_S)
        held.append(timeline.moved_deg)
        stalls += timeline.stalls_while_held()
        assert timeline.stop_after_release_s() < STOP_WITHIN_S, "the arm went on after the release"
        still_after(pendant)
    assert statistics.median(held) >= MIN_SHARE * statistics.median(api), (held, api)
    # Before the worker sent the confirmations, every press had several deadman stops. On this shared
    # machine (load average up to 15) the server itself can miss 200 ms now and then: fewer stops than
    # presses is what separates the two; benchmarks/jog.py counts them.
    assert stalls < PRESSES, f"the arm stopped {stalls} times in {PRESSES} presses while held"


@pytest.mark.measures  # a share of the API's motion, a stop time
def test_a_finger_held_on_j1_jogs_it_and_lifting_the_finger_stops_it(
    touch_page: Page, pendant: Pendant
) -> None:
    api = [api_hold(pendant.api, HOLD_S, +1 if i % 2 == 0 else -1).moved_deg for i in range(PRESSES)]
    held = []
    cdp = touch_page.context.new_cdp_session(touch_page)
    for i in range(PRESSES):
        timeline = touch_hold(touch_page, cdp, pendant.api, "J1+" if i % 2 == 0 else "J1-", HOLD_S)
        held.append(timeline.moved_deg)
        assert timeline.stop_after_release_s() < STOP_WITHIN_S, "the arm went on after the finger lifted"
        still_after(pendant)
    assert statistics.median(held) >= MIN_SHARE * statistics.median(api), (held, api)


@pytest.mark.measures  # a share of the API's motion, a stop time
def test_space_or_enter_held_on_a_focused_jog_button_jogs_and_release_stops(
    page: Page, pendant: Pendant
) -> None:
    ensure_operator(page)
    wait_settled(page)  # the page's first frames (shaders built) take the machine for a moment
    api, held = [], []
    # Each key against the API-sent hold just before it, side by side: in CI (27 Nov) a few seconds in which
    # the machine was starved shortened the first API hold (1.4 deg of 9.3) and the first key's (3.4 deg).
    for i, key in enumerate(("Space", "Enter")):
        direction = +1 if i % 2 == 0 else -1
        api.append(api_hold(pendant.api, HOLD_S, direction).moved_deg)
        timeline = key_hold(page, pendant.api, "J1+" if direction > 0 else "J1-", HOLD_S, key)
        held.append(timeline.moved_deg)
        assert timeline.stop_after_release_s() < STOP_WITHIN_S, f"the arm went on after {key} was let go"
        still_after(pendant)
    assert all(key >= MIN_SHARE * sent for key, sent in zip(held, api, strict=True)), (held, api)


HANG_S = 2.0
# A page whose main thread hangs (a stuck script, a huge frame) cannot see the release: its worker stops the
# hold after 400 ms without a sign of life and the deadman 200 ms later. Before, the worker held for 1.5 s.
STILL_AFTER_HANG_S = 1.0


@pytest.mark.measures  # stop times around a hang
def test_a_page_that_hangs_while_a_jog_is_held_stops_the_arm_until_the_button_is_pressed_again(
    page: Page, pendant: Pendant
) -> None:
    ensure_operator(page)
    wait_idle(pendant.api)
    x, y = button_centre(page, "J1+")
    page.mouse.move(x, y)
    sampler = PoseSampler(pendant.api)
    sampler.start()
    page.mouse.down()
    time.sleep(0.5)
    hung = hang_main_thread(page, sampler, HANG_S)
    time.sleep(1.0)  # the button still held
    released = sampler.mark()
    page.mouse.up()
    timeline = sampler.stop(released)
    changes = pose_changes(timeline)
    assert any(t < hung for t in changes), "the held button did not jog before the page hung"
    # Under load the page may have stalled (and the arm stopped) just before: then nothing moves in the hang.
    in_hang = [t for t in changes if hung < t < hung + HANG_S]
    assert max(in_hang, default=hung) - hung < STILL_AFTER_HANG_S, "the arm went on while the page hung"
    # The deadman's stop holds (issue 22): the page runs again with the button down, and the arm stays still.
    assert not any(t > hung + HANG_S + STILL_AFTER_HANG_S for t in changes), "the arm restarted by itself"
    assert timeline.stop_after_release_s() < STOP_WITHIN_S
    still_after(pendant)


def test_a_swipe_that_starts_on_a_jog_button_never_moves_the_arm(touch_page: Page, pendant: Pendant) -> None:
    cdp = touch_page.context.new_cdp_session(touch_page)
    for _ in range(3):
        assert touch_swipe(touch_page, cdp, pendant.api, "J1+").moved_deg < STILL_TOL_DEG
    wait_idle(pendant.api)


CLOSE_TRIES = 4
# The page draws once a second (the frame pacing benchmarks/jog.py uses): this test is about the close, and a
# software-rendered frame can hold the page's main thread past 400 ms on a busy 2-core machine, which lets the
# deadman cut the hold before the close (the designed stop, which the hang test above covers).
QUIET_PAGE = "frame_ms=1000&jog_frame_ms=1000"
QUIET_FRAME_S = 1.0  # its frames' spacing
PAGE_STOPS = {"Jog J1+ stopped: released", "Jog J1+ stopped: page closed"}
DEADMAN_S = 0.2


@pytest.mark.measures  # a stop time, the deadman's 200 ms
def test_closing_the_tab_while_a_jog_button_is_held_stops_the_arm(browser: Browser, pendant: Pendant) -> None:
    # The closing page stops the arm itself (its worker's release or its keepalive fetch, whichever comes
    # first), not the deadman once it went quiet. A try whose hold the deadman had already cut before the
    # close (the page stalled all the same) says nothing about closing and does not count; a page that never
    # sends its stop when it closes loses every try that does.
    tries: list[tuple[str, bool]] = []
    for _ in range(CLOSE_TRIES):
        tab = browser.new_page(viewport={"width": 1400, "height": 900})
        open_as_operator(tab, with_query(pendant.ui_url, QUIET_PAGE))
        # Pressed where the button stays: on a loaded machine this page's panel was seen to open a frame a
        # second, J1+ 422 px lower (half off the page) for seconds after its frames had settled, and the press
        # then missed it (4 of 12 tries beside four busy loops, 4 Dec).
        settled(tab, "J1+", still_s=QUIET_FRAME_S + 0.3)
        timeline = close_while_held(tab, pendant.api, "J1+", 0.6)
        assert timeline.moved_deg > 1.0, "the held button did not jog"
        assert timeline.stop_after_release_s() < STOP_WITHIN_S, "the arm went on after the tab closed"
        still_after(pendant)
        message, stopped_at = last_jog_stop(pendant, since=timeline.origin_wall)
        closed_at = timeline.origin_wall + timeline.released_at
        # The deadman fires DEADMAN_S after the last confirmation: one that fired sooner after the close than
        # that had lost the page's confirmations before it.
        cut_before_close = message not in PAGE_STOPS and stopped_at < closed_at + DEADMAN_S - 0.05
        tries.append((message, cut_before_close))
        if message in PAGE_STOPS:
            break
    counted = [message for message, cut_before_close in tries if not cut_before_close]
    assert counted, f"every hold was cut by a stalled page before the close: {tries}"
    assert counted[-1] in PAGE_STOPS, f"the closing page never stopped the arm itself: {tries}"


def with_query(url: str, query: str) -> str:
    return f"{url}{'&' if '?' in url else '?'}{query}"


def last_jog_stop(pendant: Pendant, since: float) -> tuple[str, float]:
    """The newest "Jog J1+ stopped: why" of the event log since `since`, and its time (epoch seconds; the
    log is written by its own thread: give it a moment)."""
    deadline = time.monotonic() + 5.0
    while True:
        query: dict[str, str | int | float] = {"text": "stopped", "limit": 1, "since": since}
        events = pendant.api.get("/pendant/events", params=query).json()["events"]
        if events:
            return str(events[0]["message"]), float(events[0]["time"])
        assert time.monotonic() < deadline, "no jog stop in the event log"
        time.sleep(0.1)


@pytest.mark.parametrize("viewport", [DESKTOP, TABLET_LANDSCAPE], ids=["1400x900", "1024x768"])
def test_all_six_axes_of_the_pad_are_on_screen_without_scrolling(
    browser: Browser, viewport: tuple[int, int]
) -> None:
    # A pendant of its own, as an operator finds it at start-up: the earlier tests' leftovers (more browsers,
    # messages under the status) make the panel above the tabs taller.
    with running_pendant() as pendant:
        page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]})
        try:
            check_pad_on_screen(page, pendant, viewport)
        finally:
            page.close()


def check_pad_on_screen(page: Page, pendant: Pendant, viewport: tuple[int, int]) -> None:
    page.goto(pendant.ui_url)
    page.locator("#jog-pad").wait_for(timeout=60_000)
    settled(page, "J1-")
    for label in ("J1-", "J1+", "J6-", "J6+"):
        box = button_box(page, label)
        assert box["y"] >= 0 and box["y"] + box["height"] <= viewport[1], label
        assert on_top(page, label), f"{label} is covered"


@pytest.mark.parametrize("viewport", [TABLET_PORTRAIT, DESKTOP], ids=["tablet-portrait", "desktop"])
def test_the_panel_leaves_the_arm_in_view(
    browser: Browser, pendant: Pendant, viewport: tuple[int, int]
) -> None:
    """The panel sits beside the 3D view, not over it: the view the camera centres the arm in is all visible,
    and it shows the arm (its pixels differ from the empty floor and sky)."""
    page = browser.new_page(viewport={"width": viewport[0], "height": viewport[1]}, has_touch=True)
    try:
        page.goto(pendant.ui_url)
        page.locator("#jog-pad").wait_for(timeout=60_000)
        settled(page, "Freeze")
        view = page.locator("canvas").first.bounding_box()
        panel_left = button_box(page, "Freeze")["x"]
        assert view is not None and view["x"] + view["width"] <= panel_left + 1, (view, panel_left)
        assert view["width"] >= 0.45 * viewport[0], f"the 3D view is only {view['width']:.0f} px wide"
        centre: FloatRect = {
            "x": view["x"] + view["width"] / 4,
            "y": view["y"] + view["height"] / 4,
            "width": view["width"] / 2,
            "height": view["height"] / 2,
        }
        # The arm's meshes arrive after the panel: the middle of the view shows the arm once they are drawn.
        deadline = time.monotonic() + ARM_DRAWN_WITHIN_S
        while dark_pixels(page.screenshot(clip=centre)) <= ARM_DARK_PIXELS:
            assert time.monotonic() < deadline, "the arm is not in the middle of the view"
            time.sleep(0.2)
        page.screenshot(path=str(ARTIFACTS / f"arm-in-view-{viewport[0]}x{viewport[1]}.png"))
    finally:
        page.close()


ARM_DRAWN_WITHIN_S = 30.0  # the meshes sent and drawn in software WebGL on a loaded machine
ARM_DARK_PIXELS = 500


def dark_pixels(png: bytes) -> int:
    """Pixels darker than the floor's grid lines: the arm's joint caps and shading."""
    import io

    import numpy as np
    from PIL import Image

    grey = np.asarray(Image.open(io.BytesIO(png)).convert("L"))
    return int(np.count_nonzero(grey < 110))
