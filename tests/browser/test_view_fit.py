"""The 3D view frames the work (issue 33): with a box in the cell where the usual view cut it off, the page
opens with the arm, its tool (the TCP frame) and the box all inside the 3D view and clear of the panel, on a
desk, an upright tablet and a phone; after the operator zooms in, Fit view frames them again. Measured by
projecting every vertex of their meshes with the page's own camera (tests/support/arm_view.py)."""

from __future__ import annotations

import time
from typing import Any

import pytest

from tests.support.arm_view import arm_on_screen, overlap
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME
from tests.support.teach_flow import TOUCH_SCREENS, open_screen

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

# Left of the usual view, low: cut at the view's left edge before (the tablet).
BOX = {
    "obstacleType": "BOX",
    "name": "crate",
    "sides": {"x": 0.25, "y": 0.25, "z": 0.2},
    "centerPosition": {
        "point": {"x": -0.35, "y": -0.7, "z": 0.1},
        "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
    },
}
WORK = ("/arm", "/tcp_frame", "/cell")
FRAMED_WITHIN_S = 60.0  # the page's panels built and its camera moved, on a loaded machine
WHEEL_PX = -300  # one turn of the wheel, towards the arm
ZOOM_WITHIN_S = 60.0
PINCH_START_PX = 20.0
PINCH_STEPS = 10


def outside(page: Any) -> list[str]:
    """What of the work is not wholly inside the 3D view, or lies under the panel."""
    found = []
    for node in WORK:
        state = arm_on_screen(page, node)
        left, top, right, bottom = state["arm"]
        view = state["canvas"]
        if left < view[0] or top < view[1] or right > view[2] or bottom > view[3]:
            found.append(f"{node} at {[round(v) for v in state['arm']]} beyond the view {view}")
        if overlap(state["arm"], state["panel"]):
            found.append(f"{node} under the panel")
    return found


def framed(page: Any) -> list[str]:
    deadline = time.monotonic() + FRAMED_WITHIN_S
    while (found := outside(page)) and time.monotonic() < deadline:
        time.sleep(0.5)
    return found


def pinch_out(page: Any, x: float, y: float, reach: float) -> None:
    """Two fingers on the view at (x, y), spread sideways to `reach` px each: a touch screen's zoom in."""
    cdp = page.context.new_cdp_session(page)

    def fingers(kind: str, apart: float) -> None:
        points = [{"x": x - apart, "y": y, "id": 0}, {"x": x + apart, "y": y, "id": 1}]
        cdp.send(
            "Input.dispatchTouchEvent", {"type": kind, "touchPoints": points if kind != "touchEnd" else []}
        )

    fingers("touchStart", PINCH_START_PX)
    for k in range(1, PINCH_STEPS + 1):
        fingers("touchMove", PINCH_START_PX + (reach - PINCH_START_PX) * k / PINCH_STEPS)
        page.wait_for_timeout(30)
    fingers("touchEnd", reach)


def zoom_in(page: Any, x: float, y: float, width: float, touch: bool) -> None:
    """The operator zooms the view in until the work no longer fits: the wheel on a desk (the view takes it
    once it has been pressed: a click first), two fingers spread apart on a touch screen."""
    if not touch:
        page.mouse.click(x, y)
    deadline = time.monotonic() + ZOOM_WITHIN_S
    while not outside(page):
        assert time.monotonic() < deadline, "the view never zoomed in"
        if touch:
            pinch_out(page, x, y, width * 0.45)
        else:
            page.mouse.wheel(0, WHEEL_PX)
        page.wait_for_timeout(300)


@pytest.mark.parametrize("screen", ["desk", "tablet", "phone"])
def test_the_view_frames_the_arm_the_tool_and_the_cell_at_load_and_after_fit(
    browser: Any, pendant: Pendant, screen: str
) -> None:
    pendant.api.put("/environment", json=BOX).raise_for_status()
    page = open_screen(browser, pendant.ui_url, screen)
    try:
        assert framed(page) == [], "at load"
        view = arm_on_screen(page)["canvas"]
        centre = ((view[0] + view[2]) / 2, (view[1] + view[3]) / 2)
        zoom_in(page, *centre, view[2] - view[0], touch=screen in TOUCH_SCREENS)
        fit = page.get_by_role("button", name="Fit view", exact=True)
        fit.scroll_into_view_if_needed()
        fit.click()
        assert framed(page) == [], "after Fit view"
    finally:
        page.close()
        pendant.api.delete("/environment").raise_for_status()


def test_a_tablet_turned_on_its_side_frames_the_work_again(browser: Any, pendant: Pendant) -> None:
    """The view changes shape under a fitted camera (upright to on its side, and back): the camera follows."""
    pendant.api.put("/environment", json=BOX).raise_for_status()
    page = open_screen(browser, pendant.ui_url, "tablet")
    try:
        assert framed(page) == [], "upright, at load"
        width, height = page.viewport_size["width"], page.viewport_size["height"]
        page.set_viewport_size({"width": height, "height": width})
        assert framed(page) == [], "turned on its side"
        page.set_viewport_size({"width": width, "height": height})
        assert framed(page) == [], "upright again"
    finally:
        page.close()
        pendant.api.delete("/environment").raise_for_status()
