"""Issue 25 in a real Chromium: each fault (a controller error, an emergency, a protective stop, a program
step refused for a box in the way) shows in the banner under Freeze with its cause, and the banner's own
buttons get the arm going again in at most two taps. Each fault runs at one of the three screen sizes
(desktop, tablet portrait, phone), and at each the arm and Freeze stay in sight."""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from playwright.sync_api import Browser, Locator, Page

from pendant.kinematics import ArmModel
from tests.support.browser_pages import ARTIFACTS
from tests.support.jog_measure import open_as_operator
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

POSE_A_DEG = [20.0, -90.0, 90.0, -90.0, -90.0, 0.0]
POSE_B_DEG = [-20.0, -80.0, 80.0, -90.0, -90.0, 0.0]
POSE_C_DEG = [0.0, -100.0, 100.0, -90.0, -90.0, 10.0]
BOX_SIDE_M = 0.08
MOVE_SPEED_PERCENT = 100.0
ANGLE_TOL_DEG = 0.05
WAIT_S = 60.0
POLL_S = 0.05
UI_TIMEOUT_MS = 30_000
MAX_TAPS = 2
MIN_ARM_VIEW_PX = 150  # the 3D view's canvas shows at least this much of itself, each way
DESKTOP, TABLET, PHONE = (1400, 900), (768, 1024), (390, 844)


def wait_until(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(POLL_S)


def move_to(pendant: Pendant, angles: list[float]) -> None:
    pendant.api.put("/pose", params={"speed": MOVE_SPEED_PERCENT}, json={"angles": angles}).raise_for_status()
    wait_until(
        lambda: pendant.status() == "IDLE" and np.allclose(pendant.pose(), angles, atol=ANGLE_TOL_DEG),
        f"the arm at {angles}",
    )


def box(name: str, centre: np.ndarray) -> dict[str, object]:
    x, y, z = (float(v) for v in centre)
    return {
        "obstacleType": "BOX",
        "name": name,
        "sides": {"x": BOX_SIDE_M, "y": BOX_SIDE_M, "z": BOX_SIDE_M},
        "centerPosition": {"point": {"x": x, "y": y, "z": z}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}},
    }


def three_moves() -> dict[str, object]:
    """A to B to C at three speeds (three requests, not one blended path: only B's is refused)."""
    zero = {"point": {"x": 0, "y": 0, "z": 0}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}}
    poses = {"A": POSE_A_DEG, "B": POSE_B_DEG, "C": POSE_C_DEG}
    return {
        "schema_version": 2,
        "name": "around_the_box",
        "waypoints": [{"name": n, "pose": {"angles": a}, "position": zero} for n, a in poses.items()],
        "steps": [
            {"kind": "move", "waypoint": n, "motion": "JOINT", "speed": s}
            for n, s in (("A", 50.0), ("B", 40.0), ("C", 30.0))
        ],
    }


@pytest.fixture
def screen(request: pytest.FixtureRequest, browser: Browser, pendant: Pendant) -> Iterator[Page]:
    width, height = request.param
    context = browser.new_context(viewport={"width": width, "height": height})
    page = context.new_page()
    open_as_operator(page, pendant.ui_url)
    yield page
    context.close()
    pendant.api.put("/sim/reset").raise_for_status()  # the next fault starts from power-on


def banner_text(page: Page) -> str:
    banner = page.locator("#recovery-banner")
    banner.wait_for(timeout=UI_TIMEOUT_MS)
    return str(banner.inner_text())


def tap(page: Page, label: str) -> None:
    page.get_by_role("button", name=label, exact=True).click(timeout=UI_TIMEOUT_MS)


def in_sight(page: Page, locator: Locator) -> dict[str, float]:
    """The part of `locator` inside the viewport, without scrolling (x, y, width, height)."""
    box = locator.bounding_box()
    assert box is not None
    view = page.viewport_size
    assert view is not None  # every page here is opened with a viewport
    left, top = max(box["x"], 0.0), max(box["y"], 0.0)
    right, bottom = min(box["x"] + box["width"], view["width"]), min(box["y"] + box["height"], view["height"])
    return {"x": left, "y": top, "width": max(0.0, right - left), "height": max(0.0, bottom - top)}


def assert_arm_and_freeze_in_sight(page: Page, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"recovery-{name}.png"))
    freeze = in_sight(page, page.get_by_role("button", name="Freeze"))
    assert freeze["width"] > 0 and freeze["height"] > 0, "Freeze is out of sight"
    canvas = in_sight(page, page.locator("canvas").first)
    assert canvas["width"] >= MIN_ARM_VIEW_PX and canvas["height"] >= MIN_ARM_VIEW_PX, (
        f"the 3D view: {canvas}"
    )
    banner = in_sight(page, page.locator("#recovery-banner"))
    assert banner["height"] > 0, "the banner is out of sight"


def back_to_idle(pendant: Pendant, page: Page, taps: list[str]) -> None:
    assert len(taps) <= MAX_TAPS
    for label in taps:
        tap(page, label)
    wait_until(lambda: pendant.status() == "IDLE", "the arm back to IDLE")
    page.locator("#recovery-banner").wait_for(state="detached", timeout=UI_TIMEOUT_MS)


@pytest.mark.parametrize("screen", [DESKTOP], indirect=True, ids=["1400x900"])
def test_a_controller_error_says_why_and_recover_brings_it_back(screen: Page, pendant: Pendant) -> None:
    page = screen
    pendant.api.put("/sim/fault/error").raise_for_status()
    text = banner_text(page)
    assert "Controller error" in text and "the arm stopped and froze" in text  # the controller's reason
    assert "Recover to continue" in text
    assert_arm_and_freeze_in_sight(page, "error")
    back_to_idle(pendant, page, ["Recover"])


@pytest.mark.parametrize("screen", [TABLET], indirect=True, ids=["768x1024"])
def test_an_emergency_keeps_the_joints_and_the_cell(screen: Page, pendant: Pendant) -> None:
    page = screen
    pendant.api.put("/environment", json=box("Fixture", np.array([0.5, -0.4, 0.1]))).raise_for_status()
    pendant.api.put("/sim/fault/emergency").raise_for_status()
    text = banner_text(page)
    assert "EMERGENCY" in text and "Release the emergency stop on the arm, then Recover" in text
    page.get_by_text("last known").first.wait_for(timeout=UI_TIMEOUT_MS)  # the joints stay, greyed
    assert_arm_and_freeze_in_sight(page, "emergency")
    back_to_idle(pendant, page, ["Reset simulator (keeps the cell)"])
    assert [o["name"] for o in pendant.api.get("/environment").json()] == ["Fixture"]


@pytest.mark.parametrize("screen", [PHONE], indirect=True, ids=["390x844"])
def test_a_protective_stop_is_named_and_recover_leaves_it(screen: Page, pendant: Pendant) -> None:
    page = screen
    pendant.api.post("/stop").raise_for_status()
    text = banner_text(page)
    assert "Protective stop" in text
    assert_arm_and_freeze_in_sight(page, "protective-stop")
    back_to_idle(pendant, page, ["Recover"])


@pytest.mark.parametrize("screen", [PHONE], indirect=True, ids=["390x844"])
def test_a_step_refused_for_a_box_names_it_and_skip_goes_on(
    screen: Page, pendant: Pendant, tmp_path: Path
) -> None:
    page = screen
    arm = ArmModel.load("pulse75")
    move_to(pendant, POSE_A_DEG)
    centre = arm.fk(np.radians(POSE_B_DEG))[:3, 3]
    pendant.api.put("/environment", json=box("Box", centre)).raise_for_status()
    program = tmp_path / "around_the_box.json"
    program.write_text(json.dumps(three_moves()))
    page.get_by_role("tab", name="Program").click()
    # A rerun of this test meets the program its first attempt left unsaved on the module's pendant, and the
    # upload asks first: Yes, as the operator would.
    page.get_by_text("Programs folder:").first.wait_for(timeout=UI_TIMEOUT_MS)
    asks = page.get_by_text("unsaved changes (autosaved)").first.is_visible()
    page.locator("input[type=file]").first.set_input_files(str(program))
    if asks:
        question = page.get_by_role("dialog").filter(has_text="Discard the unsaved changes")
        question.get_by_role("button", name="Yes", exact=True).click(timeout=UI_TIMEOUT_MS)
        question.wait_for(state="detached", timeout=UI_TIMEOUT_MS)
    page.get_by_text("around_the_box").first.wait_for(timeout=UI_TIMEOUT_MS)
    tap(page, "Run")
    text = banner_text(page)
    assert "Program stopped at step 2" in text
    assert "Collision detected" in text and "'Box'" in text  # the obstacle named
    assert_arm_and_freeze_in_sight(page, "program-step")
    assert len(["Skip step 2"]) <= MAX_TAPS
    tap(page, "Skip step 2")
    wait_until(lambda: np.allclose(pendant.pose(), POSE_C_DEG, atol=ANGLE_TOL_DEG), "the arm at C")
    wait_until(lambda: pendant.status() == "IDLE", "the run's end")
    page.locator("#recovery-banner").wait_for(state="detached", timeout=UI_TIMEOUT_MS)
