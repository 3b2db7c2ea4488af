"""The main path in a real browser: hold a jog button, release; Esc freezes a moving arm (a target typed and
run by Move J: test_typed_fields.py)."""

from __future__ import annotations

import time

import numpy as np
import pytest
from playwright.sync_api import Page

from tests.support.browser_pages import ARTIFACTS, MOVE_TIMEOUT_S, SETTLE_S, wait_idle
from tests.support.jog_measure import ensure_operator
from tests.support.launchers import Pendant

HOLD_S = 1.2
ANGLE_TOL_DEG = 0.01
FREEZE_TIMEOUT_S = 5.0
SLOW_SPEED_PERCENT = 5  # a 60° move takes several seconds: time to press Esc in the middle of it
VIEWPORT_CENTRE = (500, 450)


@pytest.mark.measures  # degrees turned in a 1.2 s hold
def test_hold_j1_plus_moves_the_arm_and_release_stops_it(page: Page, pendant: Pendant) -> None:
    wait_idle(pendant)
    before = np.array(pendant.pose())
    page.get_by_role("tab", name="Jog").click()
    # In control, and the page's frames steady: a page still building its scene stalls its main thread for
    # seconds, and the deadman rightly cuts a hold it cannot confirm (CI: the arm did not turn at all).
    ensure_operator(page)
    button = page.get_by_role("button", name="J1+", exact=True)
    box = button.bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    time.sleep(HOLD_S)
    during = np.array(pendant.pose())
    page.screenshot(path=str(ARTIFACTS / "jog-holding-j1.png"))
    page.mouse.up()
    time.sleep(SETTLE_S)
    stopped = np.array(pendant.pose())
    time.sleep(SETTLE_S)
    later = np.array(pendant.pose())

    assert during[0] > before[0] + 1.0, "holding J1+ did not turn joint 1"
    np.testing.assert_allclose(during[1:], before[1:], atol=ANGLE_TOL_DEG)
    np.testing.assert_allclose(later, stopped, atol=ANGLE_TOL_DEG)  # released: the arm stays put
    assert pendant.status() == "IDLE"


@pytest.mark.measures  # a freeze within 5 s, before a move at 5 % ends
def test_escape_anywhere_on_the_page_freezes_a_moving_arm(page: Page, pendant: Pendant) -> None:
    wait_idle(pendant)
    start = np.array(pendant.pose())
    far = (start + np.array([60.0, 0.0, 0.0, 0.0, 0.0, 0.0])).tolist()
    pendant.api.put("/pose", params={"speed": SLOW_SPEED_PERCENT}, json={"angles": far}).raise_for_status()
    deadline = time.monotonic() + MOVE_TIMEOUT_S
    while pendant.status() != "RUNNING":
        assert time.monotonic() < deadline, "the move did not start"
        time.sleep(0.05)
    page.mouse.click(VIEWPORT_CENTRE[0], VIEWPORT_CENTRE[1])  # focus on the 3D view, away from the panel
    page.keyboard.press("Escape")
    wait_idle(pendant, timeout_s=FREEZE_TIMEOUT_S)
    stopped = np.array(pendant.pose())
    time.sleep(SETTLE_S)
    np.testing.assert_allclose(pendant.pose(), stopped, atol=ANGLE_TOL_DEG)  # frozen, not finishing the move
    assert abs(stopped[0] - far[0]) > 1.0, "the move ran to its end: Esc did not freeze it"
