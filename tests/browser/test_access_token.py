"""An access token in a real browser: the URL printed at start-up gives control; a page without it cannot
move the arm, not from its buttons and not through the API. On loopback with --token, as on a LAN."""

from __future__ import annotations

import time

import numpy as np
import pytest
from playwright.sync_api import Browser, Page, expect

from pendant.access import TOKEN_HEADER, ui_url
from tests.support.browser_pages import ARTIFACTS
from tests.support.launchers import Pendant
from tests.support.shared_pendants import SharedPendants

TOKEN = "browser-test-token"
UI_TIMEOUT_MS = 15_000
HOLD_S = 1.0
ANGLE_TOL_DEG = 0.01


@pytest.fixture(scope="module")
def pendant(pendant_pool: SharedPendants) -> Pendant:
    """This module's own pendant, with an access token (from the shared ones: it stops in the background)."""
    return pendant_pool.get("--token", TOKEN)


def hold_j1_plus(page: Page) -> None:
    page.get_by_role("tab", name="Jog").click()
    box = page.get_by_role("button", name="J1+", exact=True).bounding_box()
    assert box is not None
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    time.sleep(HOLD_S)
    page.mouse.up()


def test_without_the_token_a_page_cannot_take_control_or_move_the_arm(page: Page, pendant: Pendant) -> None:
    before = pendant.pose()
    expect(page.get_by_role("button", name="J1+", exact=True)).to_be_disabled(timeout=UI_TIMEOUT_MS)
    page.get_by_role("button", name="Take control").click()
    page.get_by_text("needs its access token").first.wait_for(timeout=UI_TIMEOUT_MS)
    page.screenshot(path=str(ARTIFACTS / "token-refused.png"))
    np.testing.assert_allclose(pendant.pose(), before, atol=ANGLE_TOL_DEG)
    refused = pendant.api.put("/pose", params={"speed": 10}, json={"angles": before})
    assert refused.status_code == 401  # and the API without the header


@pytest.mark.measures  # degrees turned in a 1 s hold
def test_the_url_with_the_token_takes_control_and_jogs(browser: Browser, pendant: Pendant) -> None:
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    try:
        page.goto(ui_url("127.0.0.1", pendant.ui_port, TOKEN))
        page.get_by_role("button", name="Freeze").wait_for(timeout=30_000)
        page.get_by_role("button", name="Take control").click()
        page.get_by_text("You have control").first.wait_for(timeout=UI_TIMEOUT_MS)
        before = np.array(pendant.pose())
        hold_j1_plus(page)
        assert pendant.pose()[0] > before[0] + 1.0, "the operator's J1+ did not move the arm"
        page.screenshot(path=str(ARTIFACTS / "token-operator.png"))
    finally:
        page.close()
    accepted = pendant.api.put("/freeze", headers={TOKEN_HEADER: TOKEN})
    assert accepted.status_code == 200
