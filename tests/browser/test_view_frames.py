"""The 3D view off the page's main thread (issue 35), in a real Chromium drawing WebGL in software.

Drawn in the page, each frame of the 3D view held the page's main thread while the software renderer
finished it (the compositor's ReadPixels), and a hold's confirmations stop when the main thread is silent for
400 ms: a long hold was cut by the deadman while the arm moved. Now the view is drawn off the main thread and
still follows the arm through a 10 s hold, the release still stops it, and a page that really hangs still
stops the arm. Whether a 10 s hold is ever cut is benchmarks/frames.py's to count (with the long tasks and
frames a second): on this shared 2-core machine at load 25-30 the deadman cut holds with the view hidden too.
"""

from __future__ import annotations

import time

import pytest
from playwright.sync_api import Page

from tests.support.jog_measure import (
    PoseSampler,
    button_centre,
    ensure_operator,
    hang_main_thread,
    mouse_hold,
    pose_changes,
    wait_idle,
    wait_settled,
)
from tests.support.launchers import Pendant

LONG_HOLD_S = 10.0
STOP_WITHIN_S = 1.5  # as test_jog_hold: well inside the 3 s a continuous jog plans ahead
MIN_MOVED_DEG = 5.0  # 10 s at the jog speed moves J1 far more than this
VIEW_CATCHES_UP_S = 5.0  # a software renderer on a loaded machine: a frame or two behind the arm
HANG_S = 2.0
JOG_STARTS_WITHIN_S = 15.0  # a press to the arm moving, on a loaded 2-core machine
STILL_AFTER_HANG_S = 1.0  # the page's 400 ms without a sign of life + the server's 200 ms deadman, with room
# A 10 s hold and stop times on a real clock: alone, after the other browser tests.
pytestmark = pytest.mark.measures

VIEW_SHOWN = "() => window.__pendant && window.__pendant.viewFrames && window.__pendant.viewFrames() > 0"


def view_picture(page: Page) -> bytes:
    box = page.locator("canvas").first.bounding_box()
    assert box is not None, "no 3D view on the page"
    return page.screenshot(clip=box)


def test_the_view_follows_the_arm_through_a_10_s_hold_and_the_release_stops_it(
    page: Page, pendant: Pendant
) -> None:
    ensure_operator(page)
    page.wait_for_function(VIEW_SHOWN, timeout=60_000)
    mouse_hold(page, pendant.api, "J1-", 1.0)  # the first motion brings new things to draw (shaders to build)
    before = view_picture(page)
    wait_settled(page)  # a screenshot holds the page for a moment: press once its frames come steadily again
    timeline = mouse_hold(page, pendant.api, "J1+", LONG_HOLD_S)
    assert timeline.moved_deg > MIN_MOVED_DEG, f"the held J1+ moved J1 only {timeline.moved_deg:.2f} deg"
    assert timeline.stop_after_release_s() < STOP_WITHIN_S, "the arm went on after the release"
    deadline = time.monotonic() + VIEW_CATCHES_UP_S
    while view_picture(page) == before:
        assert time.monotonic() < deadline, "the 3D view did not follow the arm"
        time.sleep(0.2)


def test_a_page_whose_main_thread_hangs_still_stops_the_held_arm(page: Page, pendant: Pendant) -> None:
    ensure_operator(page)
    page.wait_for_function(VIEW_SHOWN, timeout=60_000)
    wait_idle(pendant.api)
    page.mouse.move(*button_centre(page, "J1-"))
    sampler = PoseSampler(pendant.api)
    sampler.start()
    page.mouse.down()
    # The hang starts once the hold is seen to move the arm (a loaded machine takes a moment to start it).
    moving = sampler.wait_moving(JOG_STARTS_WITHIN_S)
    hung = hang_main_thread(page, sampler, HANG_S)
    released = sampler.mark()
    page.mouse.up()
    changes = pose_changes(sampler.stop(released))
    assert moving and any(t < hung for t in changes), "the held button did not jog before the page hung"
    late = [t for t in changes if hung + STILL_AFTER_HANG_S < t < hung + HANG_S]
    assert not late, (
        f"the arm went on {max(late, default=hung) - hung:.2f} s into the page's {HANG_S:.0f} s hang"
    )
