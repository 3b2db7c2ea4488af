"""The Dashboard in a real browser: the legend shows each joint's value (not "--") with its unit, the
event log lists what the API did, and "Join from a tablet" says how to expose a pendant on loopback."""

from __future__ import annotations

import re
import time

import pytest

from tests.support.shared_pendants import NOT_REAL_TIME

from .conftest import ARTIFACTS, Pendant

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

PLOTS_FILL_S = 2.0
TIMEOUT_MS = 30_000


def test_dashboard_plots_log_and_join_qr(page, pendant: Pendant) -> None:
    assert pendant.api.put("/signal/output/1/high").status_code == 200  # something for the event log
    page.get_by_role("tab", name="Dashboard").click(no_wait_after=True)
    time.sleep(PLOTS_FILL_S)
    legend = page.locator(".u-legend").first
    legend.wait_for(timeout=TIMEOUT_MS)
    text = legend.inner_text()
    assert re.search(r"J1 -?\d+\.\d °", text), text
    assert "--" not in text
    logged = page.locator("#event-log").get_by_text("PUT /signal/output/1/high -> 200")
    logged.first.wait_for(timeout=TIMEOUT_MS)  # newest first (the log on disk may hold earlier runs')
    page.screenshot(path=str(ARTIFACTS / "dashboard.png"), full_page=True)

    page.get_by_role("button", name="Join from a tablet (QR)").click()
    note = page.locator("#join-loopback")  # the test's pendant listens on loopback: no tablet could join
    note.wait_for(timeout=TIMEOUT_MS)
    assert "pendant --host 0.0.0.0" in note.inner_text()
