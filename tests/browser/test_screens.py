"""The operator is never left guessing, in a real browser: axe-core finds no serious or critical violation on
any tab (operator and viewer), inputs are found by their label, Record after a reload appends, the Cell tab's
Update moves the chosen obstacle (no second one), and a viewer's controls are greyed out saying why."""

from __future__ import annotations

import time
from typing import Any

import pytest
from axe_playwright_python.sync_playwright import Axe

from pendant.ui.kit.view_only import VIEW_ONLY_HINT
from tests.support.browser_pages import ARTIFACTS, choose, move_to, obstacles, sent, take_control
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

TABS = ("Jog", "Target", "Program", "Cell", "IO", "Robot", "Simulator", "Dashboard")
BLOCKING_IMPACTS = ("serious", "critical")
UI_TIMEOUT_MS = 30_000
PAGE_LOAD_TIMEOUT_MS = 120_000  # a second software-WebGL page on a loaded machine
SETTLE_MS = 800  # the accessibility pass runs 150 ms after the DOM settles; a software-rendered frame on top
POSE_A_DEG = [25.0, -90.0, 90.0, -90.0, -90.0, 0.0]
POSE_B_DEG = [-25.0, -80.0, 80.0, -90.0, -90.0, 0.0]
POSE_C_DEG = [0.0, -100.0, 100.0, -90.0, -90.0, 0.0]
CRATE = {
    "obstacleType": "BOX",
    "name": "crate",
    "sides": {"x": 0.1, "y": 0.1, "z": 0.1},
    "centerPosition": {
        "point": {"x": 0.4, "y": 0.4, "z": 0.05},
        "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
    },
}
MOVED_X_MM = 450.0
SHOWN_WITHIN_S = 30.0


def blocking_violations(page: Any) -> list[str]:
    results = Axe().run(page)
    return [
        f"{v['id']} ({v['impact']}): {v['help']} at {[n['target'] for n in v['nodes'][:3]]}"
        for v in results.response["violations"]
        if v["impact"] in BLOCKING_IMPACTS
    ]


def open_tab(page: Any, name: str) -> None:
    page.get_by_role("tab", name=name).click(no_wait_after=True)
    page.wait_for_timeout(SETTLE_MS)


def test_axe_finds_no_serious_or_critical_violation_on_any_tab(page: Any) -> None:
    take_control(page)
    found = {}
    for tab in TABS:
        open_tab(page, tab)
        found[tab] = blocking_violations(page)
    assert found == {tab: [] for tab in TABS}


LEGEND_J1_DEG = "30"  # a target away from home: its ghost shows


def test_the_legend_over_the_view_names_the_ghost_shown(page: Any) -> None:
    take_control(page)
    open_tab(page, "Target")
    legend = page.locator("#ghost-legend")
    box = page.get_by_label("J1 °", exact=True)
    box.fill(LEGEND_J1_DEG)
    box.press("Enter")
    page.get_by_text("Ghost: target").wait_for(timeout=UI_TIMEOUT_MS)
    assert legend.is_visible()
    shown = legend.bounding_box()
    canvas = page.locator("canvas").first.bounding_box()
    assert shown is not None and canvas is not None
    assert canvas["x"] <= shown["x"] and shown["x"] + shown["width"] <= canvas["x"] + canvas["width"]
    assert canvas["y"] <= shown["y"] and shown["y"] + shown["height"] <= canvas["y"] + canvas["height"]
    assert blocking_violations(page) == []
    page.screenshot(path=str(ARTIFACTS / "screens-ghost-legend.png"))
    page.get_by_role("button", name="Target = current").click()
    legend.wait_for(state="hidden", timeout=UI_TIMEOUT_MS)  # no target, no ghost: no legend


def test_inputs_are_found_by_their_label(page: Any) -> None:
    open_tab(page, "Jog")
    speed = page.get_by_label("Speed %", exact=True)
    assert speed.is_visible() and speed.evaluate("e => e.tagName") == "INPUT"
    open_tab(page, "Cell")
    for label in ("Obstacle", "Kind", "Name", "Position mm", "Size mm"):
        assert page.get_by_label(label, exact=True).first.is_visible(), label


def test_record_after_a_reload_appends_at_the_end(page: Any, pendant: Pendant) -> None:
    take_control(page)
    open_tab(page, "Program")
    for k, pose in enumerate((POSE_A_DEG, POSE_B_DEG), start=1):
        move_to(pendant, pose)
        page.get_by_role("button", name="Record", exact=True).click()
        page.get_by_text(f"{k}. Move J to P{k} @ 20%").first.wait_for(timeout=UI_TIMEOUT_MS)
    page.reload()
    page.get_by_role("button", name="Freeze").wait_for(timeout=UI_TIMEOUT_MS)
    take_control(page)
    open_tab(page, "Program")
    # A reloaded page selects nothing, and says so.
    page.locator("input[value='(no step selected)']:visible").first.wait_for(timeout=UI_TIMEOUT_MS)
    move_to(pendant, POSE_C_DEG)
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("3. Move J to P3 @ 20%").first.wait_for(timeout=UI_TIMEOUT_MS)
    assert page.get_by_text("1. Move J to P1 @ 20%").first.is_visible()
    page.screenshot(path=str(ARTIFACTS / "screens-record-after-reload.png"))


def test_update_moves_the_chosen_obstacle_and_adds_none(page: Any, pendant: Pendant) -> None:
    pendant.api.put("/environment", json=CRATE).raise_for_status()
    try:
        take_control(page)
        open_tab(page, "Cell")
        choose(page, "(new obstacle)", "crate")
        x = page.get_by_label("Position mm", exact=True)
        x.fill(f"{MOVED_X_MM:.0f}, 400, 50")  # the crate's y and z stay
        x.press("Enter")
        sent(page)
        page.get_by_role("button", name="Update selected obstacle").click()
        deadline = time.monotonic() + SHOWN_WITHIN_S
        while obstacles(pendant)[0]["centerPosition"]["point"]["x"] != pytest.approx(MOVED_X_MM / 1000):
            assert time.monotonic() < deadline, "the update did not reach the controller"
            time.sleep(0.1)
        assert [o["name"] for o in obstacles(pendant)] == ["crate"]  # moved, not a second one
    finally:
        pendant.api.delete("/environment").raise_for_status()


def test_a_viewer_sees_its_controls_greyed_out_with_the_reason(browser: Any, page: Any) -> None:
    take_control(page)  # this page operates; another browser watches
    viewer = browser.new_page(viewport={"width": 1400, "height": 900})
    try:
        viewer.goto(page.url)
        viewer.get_by_role("button", name="Freeze").wait_for(timeout=PAGE_LOAD_TIMEOUT_MS)
        viewer.get_by_text("has control").first.wait_for(timeout=UI_TIMEOUT_MS)
        # Disabled once the page's panels are all built (the role is applied last; "has control" comes first).
        jog = viewer.locator("button[aria-label='J1+'][disabled]")
        jog.wait_for(timeout=UI_TIMEOUT_MS)
        assert jog.is_disabled() and jog.get_attribute("title") == VIEW_ONLY_HINT
        open_tab(viewer, "Program")
        assert viewer.get_by_role("button", name="Record", exact=True).is_disabled()
        viewer.screenshot(path=str(ARTIFACTS / "screens-viewer.png"))
        found = {}
        for tab in TABS:
            open_tab(viewer, tab)
            found[tab] = blocking_violations(viewer)
        assert found == {tab: [] for tab in TABS}
    finally:
        viewer.close()
