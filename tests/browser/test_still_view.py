"""The 3D view is drawn again only when its picture changes (still_view.js), in a real Chromium drawing WebGL
in software: at rest a page draws nothing new, not viser's heartbeat frame a second (each a frame of software
rendering for the same picture); a motion, a turn of the camera and a change of size are drawn, as before.
What that saves in CPU is benchmarks/idle_page.py's to measure."""

from __future__ import annotations

import time

import pytest
from playwright.sync_api import Page

from tests.support.launchers import Pendant

pytestmark = pytest.mark.time_scale(5.0)  # not about real time: the simulator's motions 5 times faster

REST_S = 3.0  # viser's client asks for a frame a second at rest: three of them, none drawn
SAFETY_NET_S = 5.0  # still_view.js draws at least this often whatever
SETTLE_TIMEOUT_S = 30.0
DRAWN_TIMEOUT_S = 30.0
# Counts the frames three.js draws (it clears once per frame).
COUNT_FRAMES = """
window.__clears = 0;
const clear = WebGL2RenderingContext.prototype.clear;
WebGL2RenderingContext.prototype.clear = function (...args) {
  window.__clears++;
  return clear.apply(this, args);
};
"""
SKIPPED = "window.__pendant.stillSkipped"
NUDGE_J1 = {"angles": [20.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def clears(page: Page) -> int:
    return int(page.evaluate("window.__clears"))


def at_rest(page: Page) -> None:
    """Until viser has asked for a frame and none was drawn: the picture on screen is the scene as it is (the
    page's load, the camera's fit and any motion done)."""
    deadline = time.monotonic() + SETTLE_TIMEOUT_S
    while True:
        before, skipped = clears(page), int(page.evaluate(SKIPPED))
        page.wait_for_timeout(1500)
        if clears(page) == before and int(page.evaluate(SKIPPED)) > skipped:
            return
        assert time.monotonic() < deadline, "the page never stopped drawing with the arm at rest"


def view_picture(page: Page) -> bytes:
    box = page.locator("canvas[data-pendant-view]").bounding_box()
    assert box is not None, "no 3D view on the page"
    return page.screenshot(clip=box)


@pytest.fixture
def counted_page(page: Page) -> Page:
    page.context.add_init_script(COUNT_FRAMES)
    page.reload()
    page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=60_000)
    page.wait_for_function("() => window.__clears > 0", timeout=60_000)
    return page


def test_at_rest_the_view_draws_nothing_new(counted_page: Page, pendant: Pendant) -> None:
    page = counted_page
    at_rest(page)
    before, skipped = clears(page), int(page.evaluate(SKIPPED))
    page.wait_for_timeout(REST_S * 1000)
    assert clears(page) - before <= 1, f"{clears(page) - before} frames drawn in {REST_S:g} s at rest"
    assert int(page.evaluate(SKIPPED)) > skipped, "viser asked for no frame at rest: nothing was left undrawn"
    # The safety net: a frame is drawn every few seconds whatever.
    page.wait_for_function(f"() => window.__clears > {clears(page)}", timeout=(SAFETY_NET_S + 5) * 1000)


def test_a_motion_a_turn_of_the_camera_and_a_new_size_are_drawn(counted_page: Page, pendant: Pendant) -> None:
    page = counted_page
    at_rest(page)
    rest = view_picture(page)
    pendant.api.put("/pose", params={"speed": 30}, json=NUDGE_J1).raise_for_status()
    wait_until_drawn(page, rest, "the arm's move")

    at_rest(page)
    moved = view_picture(page)
    box = page.locator("canvas[data-pendant-view]").bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] * 0.3, box["y"] + box["height"] * 0.5)
    page.mouse.wheel(0, 400)  # zoom out
    wait_until_drawn(page, moved, "a turn of the mouse wheel")

    at_rest(page)
    zoomed = clears(page)
    page.set_viewport_size({"width": 1200, "height": 800})
    deadline = time.monotonic() + DRAWN_TIMEOUT_S
    while clears(page) == zoomed:
        assert time.monotonic() < deadline, "the page's new size was not drawn"
        page.wait_for_timeout(100)


def wait_until_drawn(page: Page, before: bytes, what: str) -> None:
    deadline = time.monotonic() + DRAWN_TIMEOUT_S
    while view_picture(page) == before:
        assert time.monotonic() < deadline, f"the 3D view did not show {what}"
        page.wait_for_timeout(200)
