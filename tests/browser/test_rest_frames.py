"""viser's heartbeat frame comes every 5 s, not every second, where WebGL is drawn in software
(pendant/ui/page/rest_frames.js): at rest each of its frames is the same picture drawn again, 0.5-0.7 s of
Chromium's GPU process on the suite's machine (benchmarks/idle_page.py). The hook finds the heartbeat by
its shape in viser 1.1.1's client; a viser whose heartbeat changed shape fails here, not silently. A change
that asks for a frame is still drawn at once (test_cell_page: a box added through the API)."""

from __future__ import annotations

import pytest
from playwright.sync_api import Page

from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)


def test_viser_s_heartbeat_is_found_and_slowed(page: Page) -> None:
    assert page.evaluate("window.__pendant.software"), "this suite's Chromium draws WebGL in software"
    assert page.evaluate("window.__pendant.heartbeat") == "slowed"
