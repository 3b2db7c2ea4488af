"""The Remote control switch in a real browser: the operator turns it off in the page and an API client can
no longer move the arm (it is told who has control); turned on again, the client's command runs."""

from __future__ import annotations

import json
import time

import httpx
import numpy as np
import pytest
from playwright.sync_api import Page

from tests.support.browser_pages import ARTIFACTS
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

UI_TIMEOUT_MS = 15_000
SWITCH_TIMEOUT_S = 10.0
TARGET = [15.0, -90.0, 90.0, -90.0, -90.0, 0.0]
ANGLE_TOL_DEG = 0.01


def put_target(pendant: Pendant, angles: list[float] = TARGET) -> httpx.Response:
    return pendant.api.put("/pose", params={"speed": 50}, json={"angles": angles})


def wait_for_status(pendant: Pendant, status: int, angles: list[float]) -> httpx.Response:
    """Send Move J to `angles` until the API answers `status`. Where the arm already is, while the switch's
    click may not have reached the pendant yet: a probe that still passed then moves nothing (TARGET did,
    under load, CI 27 Nov)."""
    deadline = time.monotonic() + SWITCH_TIMEOUT_S
    while True:
        answer = put_target(pendant, angles)
        if answer.status_code == status:
            return answer
        assert time.monotonic() < deadline, f"the API still answers {answer.status_code}: {answer.text}"
        time.sleep(0.1)


def test_the_operator_turns_remote_control_off_and_on_in_the_page(page: Page, pendant: Pendant) -> None:
    page.get_by_text("You have control").first.wait_for(timeout=UI_TIMEOUT_MS)
    # viser draws the label beside the box, not as its <label>: the box is the checkbox in the label's row.
    row = page.get_by_text("Remote control", exact=True).locator("xpath=ancestor::div[.//input][1]")
    switch = row.locator("input[type=checkbox]")
    assert switch.is_checked()  # the simulator on loopback: scripts work out of the box
    before = pendant.pose()

    row.locator(".mantine-Checkbox-inner").click()
    assert not switch.is_checked()
    wait_for_status(pendant, 403, before)
    refused = put_target(pendant)
    assert refused.status_code == 403, refused.text
    page.screenshot(path=str(ARTIFACTS / "remote-control-off.png"))
    message = json.loads(refused.text)
    assert "Remote control is off" in message and "browser #" in message
    time.sleep(0.5)
    np.testing.assert_allclose(pendant.pose(), before, atol=ANGLE_TOL_DEG)
    assert pendant.api.put("/freeze").status_code == 200  # stopping stays open

    row.locator(".mantine-Checkbox-inner").click()
    assert switch.is_checked()
    deadline = time.monotonic() + SWITCH_TIMEOUT_S
    while (answer := put_target(pendant)).status_code != 200:
        assert time.monotonic() < deadline, answer.text
        time.sleep(0.1)
    deadline = time.monotonic() + SWITCH_TIMEOUT_S
    while not np.allclose(pendant.pose(), TARGET, atol=ANGLE_TOL_DEG):
        assert time.monotonic() < deadline, "the API's command did not run once Remote control was on"
        time.sleep(0.1)
