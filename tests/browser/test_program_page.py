"""Teach and play back in a real browser: record two waypoints (with a DO set between them), run, and check
the arm passed through both: DO1 went HIGH while the arm was at the first, and it ended at the second."""

from __future__ import annotations

import time

import numpy as np
import pytest
from playwright.sync_api import Page

from tests.support.browser_pages import (
    ANGLE_TOL_DEG,
    ARTIFACTS,
    AWAY_DEG,
    POLL_S,
    POSE_A_DEG,
    POSE_B_DEG,
    RUN_TIMEOUT_S,
    UI_TIMEOUT_MS,
    move_to,
)
from tests.support.launchers import Pendant

AT_WAYPOINT_TOL_DEG = 0.5  # two HTTP reads apart, around an arm coming to rest at P1 and leaving it


def output(pendant: Pendant, port: int) -> str:
    return pendant.api.get(f"/signal/output/{port}").text.strip('"')


@pytest.mark.measures  # where the arm is between two API reads
def test_record_two_waypoints_and_play_them_back(page: Page, pendant: Pendant) -> None:
    pendant.api.put("/signal/output/1/low").raise_for_status()
    take_control = page.get_by_role("button", name="Take control")
    if take_control.is_visible():  # on loopback the first browser already has control
        take_control.click()
    page.get_by_role("tab", name="Program").click()

    move_to(pendant, POSE_A_DEG)
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("1. Move J to P1 @ 20%").first.wait_for(timeout=UI_TIMEOUT_MS)
    page.get_by_role("button", name="Set DO", exact=True).click()  # after the selected step: DO1 HIGH
    page.get_by_text("2. Set DO1 HIGH").first.wait_for(timeout=UI_TIMEOUT_MS)
    move_to(pendant, POSE_B_DEG)
    page.get_by_role("button", name="Record", exact=True).click()
    page.get_by_text("3. Move J to P2 @ 20%").first.wait_for(timeout=UI_TIMEOUT_MS)
    move_to(pendant, AWAY_DEG)
    page.screenshot(path=str(ARTIFACTS / "program-recorded.png"))

    page.get_by_role("button", name="Run", exact=True).click()
    poses_around_do_high: tuple[list[float], list[float]] | None = None
    deadline = time.monotonic() + RUN_TIMEOUT_S
    while True:
        pose = pendant.pose()
        if poses_around_do_high is None and output(pendant, 1) == "HIGH":
            # The arm may arrive at P1 between the two reads, or just leave it: keep both sides.
            poses_around_do_high = (pose, pendant.pose())
        if poses_around_do_high is not None and np.allclose(pose, POSE_B_DEG, atol=ANGLE_TOL_DEG):
            break
        assert time.monotonic() < deadline, f"the program did not reach P2 (arm at {pose})"
        time.sleep(POLL_S)
    page.get_by_text("Finished").first.wait_for(timeout=UI_TIMEOUT_MS)
    page.screenshot(path=str(ARTIFACTS / "program-finished.png"))

    # DO1 is set between the two moves, so when it went HIGH the arm was at P1 (P2 and the start are 25°
    # away in J1; within a few milliseconds of P1 the arm is within hundredths of a degree of it).
    assert poses_around_do_high is not None
    nearest = min(float(np.max(np.abs(np.subtract(p, POSE_A_DEG)))) for p in poses_around_do_high)
    assert nearest < AT_WAYPOINT_TOL_DEG, f"DO1 went HIGH {nearest:.2f}° away from P1"
    np.testing.assert_allclose(pendant.pose(), POSE_B_DEG, atol=ANGLE_TOL_DEG)
    assert pendant.status() == "IDLE"
    # Recording autosaved: a kill of the pendant now would lose nothing.
    assert "P2" in (pendant.programs / ".autosave.json").read_text()
