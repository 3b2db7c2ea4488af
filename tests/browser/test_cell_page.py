"""The cell in a real browser: an obstacle a script adds appears in the 3D view; one added in the page is
refused-by-collision for a move through it; a protective stop bound to DI1 fires when DI1 goes high."""

from __future__ import annotations

import io
import time

import numpy as np
import pytest
from PIL import Image
from playwright.sync_api import Page

from tests.support.browser_pages import ARTIFACTS, SETTLE_S, obstacles, sent, wait_idle
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME
from tests.support.typed import typed_box

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

SHOWN_WITHIN_S = 15.0  # the page's own check and redraw, on a loaded 2-core machine
ORANGE_PIXELS_MIN = 2000  # a 30 cm box in the default view covers tens of thousands of pixels
SIDE_M = 0.3
SCENE_WIDTH_PX = 950  # the page is 1400 px wide; the control panel takes its right side
BOX_CENTRE_M = (0.35, -0.45, SIDE_M / 2)  # in front of the arm, in the default camera's view
# Where the flange passes when joint 1 turns 45° from home (whole mm: the Cell tab's fields step by 1 mm).
WALL_MM = (-244.0, -415.0, 485.0)
WALL_SIDE_MM = 120.0


def orange_pixels(page: Page) -> int:
    """How many pixels of the 3D view (left of the control panel) are the obstacles' translucent orange: warm
    (red well above blue), where the floor, the arm and the sky are grey or white."""
    rgb = np.asarray(Image.open(io.BytesIO(page.screenshot())).convert("RGB")).astype(int)
    rgb = rgb[:, :SCENE_WIDTH_PX]
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    return int(np.count_nonzero((r > 150) & (r - b > 40) & (r >= g) & (g > b)))


def box(name: str, centre: tuple[float, float, float], side: float) -> dict[str, object]:
    x, y, z = centre
    return {
        "obstacleType": "BOX",
        "name": name,
        "sides": {"x": side, "y": side, "z": side},
        "centerPosition": {"point": {"x": x, "y": y, "z": z}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}},
    }


def fill_after(page: Page, label: str, values: tuple[object, ...]) -> None:
    """Type `values` into the box beside the visible field labelled `label` (a vector's as "x, y, z") and
    commit it with Enter, as a person types them."""
    field = page.locator(f"xpath=//label[normalize-space()='{label}']/following::input[1] >> visible=true")
    field.first.fill(", ".join(str(value) for value in values))
    field.first.press("Enter")
    sent(page)


def test_an_obstacle_added_through_the_api_appears_in_the_scene(page: Page, pendant: Pendant) -> None:
    wait_idle(pendant)
    time.sleep(SETTLE_S)
    before = orange_pixels(page)
    added = pendant.api.put("/environment", json=box("script box", BOX_CENTRE_M, SIDE_M))
    assert added.status_code == 200, added.text
    try:
        deadline = time.monotonic() + SHOWN_WITHIN_S
        while (after := orange_pixels(page)) < before + ORANGE_PIXELS_MIN:
            assert time.monotonic() < deadline, f"the box did not appear ({before} -> {after} orange pixels)"
            time.sleep(0.2)
        page.screenshot(path=str(ARTIFACTS / "cell-obstacle-from-api.png"))
        page.get_by_role("tab", name="Cell").click()
        page.get_by_text("1 obstacle(s)").wait_for(timeout=SHOWN_WITHIN_S * 1000)
    finally:
        pendant.api.delete("/environment").raise_for_status()
    deadline = time.monotonic() + SHOWN_WITHIN_S
    while orange_pixels(page) > before + ORANGE_PIXELS_MIN // 2:
        assert time.monotonic() < deadline, "the deleted box stayed in the scene"
        time.sleep(0.2)


def test_an_obstacle_added_in_the_page_refuses_a_move_through_it(page: Page, pendant: Pendant) -> None:
    wait_idle(pendant)
    home = np.array(pendant.pose())
    # The box goes where the flange passes when joint 1 turns 45° from home: it blocks turning it 90°.
    page.get_by_role("tab", name="Cell").click()
    fill_after(page, "Name", ("wall",))
    fill_after(page, "Position mm", WALL_MM)
    fill_after(page, "Size mm", (WALL_SIDE_MM,) * 3)
    page.get_by_role("button", name="Add obstacle").click()
    try:
        deadline = time.monotonic() + SHOWN_WITHIN_S
        while [o["name"] for o in obstacles(pendant)] != ["wall"]:
            assert time.monotonic() < deadline, "the page's obstacle did not reach the controller"
            time.sleep(0.1)
        cell = obstacles(pendant)
        point = cell[0]["centerPosition"]["point"]
        assert [round(point[k] * 1000) for k in "xyz"] == list(WALL_MM), "the wall is not where typed"

        target = home.copy()
        target[0] += 90.0
        page.get_by_role("tab", name="Target").click()
        page.get_by_role("button", name="Move J").wait_for(timeout=SHOWN_WITHIN_S * 1000)  # the tab is shown
        j1 = typed_box(page, "J1 °")
        j1.fill(f"{target[0]:.1f}")
        j1.press("Enter")
        page.get_by_text("the path to the target passes through 'wall'").wait_for(
            timeout=SHOWN_WITHIN_S * 1000
        )
        assert page.get_by_role("button", name="Move J").is_disabled()
        page.screenshot(path=str(ARTIFACTS / "cell-path-through-obstacle.png"))

        refused = pendant.api.put("/pose", params={"speed": 50}, json={"angles": target.tolist()})
        assert refused.status_code == 412
        assert "Collision detected" in refused.text
        time.sleep(SETTLE_S)
        np.testing.assert_allclose(pendant.pose(), home, atol=0.01)  # the arm never moved
    finally:
        pendant.api.delete("/environment").raise_for_status()
        page.get_by_role("button", name="Target = current").click()


def test_a_protective_stop_bound_to_di1_fires_when_di1_goes_high(page: Page, pendant: Pendant) -> None:
    wait_idle(pendant)
    page.get_by_role("tab", name="Robot").click()
    page.get_by_text("Protective stop on input").click()
    page.get_by_role("button", name="Bind stop", exact=True).click()
    time.sleep(SETTLE_S)
    try:
        page.get_by_role("tab", name="Simulator").click()
        page.get_by_label("Set DI1").check()
        deadline = time.monotonic() + SHOWN_WITHIN_S
        while pendant.status() != "ERROR":
            assert time.monotonic() < deadline, "DI1 going high did not stop the arm"
            time.sleep(0.1)
        failures = pendant.api.get("/status/failure").json()
        assert "digital input 1 went HIGH" in failures[-1]["message"]
        page.get_by_role("tab", name="Dashboard").click()
        page.get_by_text("digital input 1 went HIGH").first.wait_for(timeout=SHOWN_WITHIN_S * 1000)
        page.screenshot(path=str(ARTIFACTS / "protective-stop-di1.png"))
        moved = pendant.api.put("/pose", params={"speed": 50}, json={"angles": pendant.pose()})
        assert moved.status_code == 412  # a stopped arm refuses motion until Recover
    finally:
        pendant.api.delete("/stop/bind")
        pendant.api.put("/sim/signal/input/1/low")
        page.get_by_role("button", name="Recover").first.click()
        wait_idle(pendant)
