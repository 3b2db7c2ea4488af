"""In a real browser, on a "real" arm (a `pendant --no-ui` process behind `pendant --robot`): Run waits for a
pre-flight; Check marks the step whose move would hit a box, says it in words and changes nothing on the arm;
the operator's override after a confirmation is logged with who gave it."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from playwright.sync_api import Browser, Page

from pendant.controller.types import MotionParams, MotionStatus, Pose
from pendant.program import ProgramStore
from pendant.remote import RemoteController
from tests.support.browser_pages import ARTIFACTS
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant as running_arm
from tests.support.launchers import running_pendant_ui as running_pendant
from tests.support.preflight_scene import BOX_NAME, LEFT_DEG, box_in_the_way, swing_program
from tests.support.shared_pendants import NOT_REAL_TIME
from tests.support.waiting import wait_until

UI_TIMEOUT_MS = 90_000  # a loaded 2-core machine builds a page slowly


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Pendant, RemoteController]]:
    programs = tmp_path_factory.mktemp("programs")
    ProgramStore(programs).autosave(swing_program(), None, True)  # the page opens with this program
    # The arm's simulator runs faster: the test is about what the page says, not about real time.
    with running_arm("--time-scale", str(NOT_REAL_TIME)) as arm_url:
        arm = RemoteController(arm_url)
        arm.set_pose(Pose(angles=list(LEFT_DEG)), MotionParams(speed=100.0))
        wait_until(lambda: arm.get_motion_status() is MotionStatus.IDLE, timeout_s=20)
        arm.add_obstacle(box_in_the_way())
        with running_pendant("--robot", arm_url, "--programs", str(programs)) as served:
            yield served, arm


@pytest.fixture
def page(browser: Browser, rig: tuple[Pendant, RemoteController]) -> Iterator[Page]:
    served, _ = rig
    ARTIFACTS.mkdir(exist_ok=True)
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.goto(served.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=UI_TIMEOUT_MS)
    yield page
    page.close()


def test_check_marks_the_failing_step_and_run_waits_for_it(
    page: Page, rig: tuple[Pendant, RemoteController]
) -> None:
    served, arm = rig
    take_control = page.get_by_role("button", name="Take control")
    if take_control.is_visible():
        take_control.click()
    page.get_by_role("tab", name="Program").click(timeout=UI_TIMEOUT_MS)
    before = (arm.get_pose().angles, arm.get_obstacles())

    page.get_by_role("button", name="Run", exact=True).click(timeout=UI_TIMEOUT_MS)
    page.get_by_text("Check the program first").first.wait_for(timeout=UI_TIMEOUT_MS)

    page.get_by_role("button", name="Check", exact=True).click(timeout=UI_TIMEOUT_MS)
    page.get_by_text("✘ Step 3 (Move J to right").first.wait_for(timeout=UI_TIMEOUT_MS)
    marked = page.get_by_text(f"3. Move J to right @ 15% · ✘ the gripper would hit '{BOX_NAME}'")
    marked.first.wait_for(timeout=UI_TIMEOUT_MS)
    assert page.get_by_text("○ not checked").count() >= 1 and page.get_by_text("✘ not checked").count() == 0
    page.screenshot(path=str(ARTIFACTS / "program-check-failed.png"))
    assert (arm.get_pose().angles, arm.get_obstacles()) == before  # checked on the twin: nothing moved

    page.get_by_role("button", name="Run without check").click(timeout=UI_TIMEOUT_MS)
    page.get_by_role("button", name="Yes, run without check").click(timeout=UI_TIMEOUT_MS)
    # The arm itself refuses the move into the box: the run fails at the step the check marked.
    page.get_by_text("Step 3 (Move J to right @ 15%) failed").first.wait_for(timeout=UI_TIMEOUT_MS)
    answer = served.api.get("/pendant/events", params={"text": "without a passing pre-flight"})
    events = answer.json()["events"]
    assert events, "the override is not in the event log"
    assert events[0]["source"].startswith("browser") and "'swing'" in events[0]["message"]
