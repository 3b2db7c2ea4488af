"""The Dashboard in a real browser: the legend shows each joint's value (not "--") with its unit, the
event log lists what the API did, and "Join from a tablet" says how to expose a pendant on loopback."""

from __future__ import annotations

import re

import pytest
from playwright.sync_api import Page, expect

from tests.support.browser_pages import ARTIFACTS, open_tab
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

JOINT_VALUE = re.compile(r"J1 -?\d+\.\d °")
TIMEOUT_MS = 30_000


def test_dashboard_plots_log_and_join_qr(page: Page, pendant: Pendant) -> None:
    assert pendant.api.put("/signal/output/1/high").status_code == 200  # something for the event log
    open_tab(page, "Dashboard")
    legend = page.locator(".u-legend").first
    expect(legend).to_contain_text(JOINT_VALUE, timeout=TIMEOUT_MS)  # the plots have filled in
    text = legend.inner_text()
    assert JOINT_VALUE.search(text), text
    assert "--" not in text
    logged = page.locator("#event-log").get_by_text("PUT /signal/output/1/high -> 200")
    logged.first.wait_for(timeout=TIMEOUT_MS)  # newest first (the log on disk may hold earlier runs')
    page.screenshot(path=str(ARTIFACTS / "dashboard.png"), full_page=True)

    page.get_by_role("button", name="Join from a tablet (QR)").click()
    note = page.locator("#join-loopback")  # the test's pendant listens on loopback: no tablet could join
    note.wait_for(timeout=TIMEOUT_MS)
    assert "pendant --host 0.0.0.0" in note.inner_text()
