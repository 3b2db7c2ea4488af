"""The Dashboard's live plots go to a browser only while its page shows the tab (issue 37: 60 viewers on the
Jog tab were each sent three plots twice a second): a real page on loopback, a browser as a bare websocket
that reads every frame and says what client_page.js says when the tab's marker comes into view and leaves.
(Chromium's side, the page saying so itself: tests/browser/test_dashboard_page.py, whose legend fills in only
once the tab is shown.)"""

from __future__ import annotations

import asyncio
import re
import time
from collections.abc import Iterator

import pytest
import websockets
import zstandard

from pendant.sim import SimController
from pendant.ui.app import PendantUI
from tests.support.headless_viewer import click_message, next_messages, open_viewer
from tests.support.pages import pendant_page

PANEL_TIMEOUT_S = 60.0  # generous: the machine may be loaded; nothing here measures speed
WATCH_S = 5.0  # ten plot refreshes (2 Hz) when the tab is shown
SETTLE_S = 2.0  # four refreshes without the plots: what was on its way has come
SETTLE_TIMEOUT_S = 30.0
MARKER = re.compile(r'data-tab-shown="([0-9a-f-]+)" data-tab-hidden="([0-9a-f-]+)"')


@pytest.fixture
def page(sim: SimController) -> Iterator[PendantUI]:
    with pendant_page(sim, sim.arm) as page:
        page.start()  # the refresh loop: it pushes the plots
        yield page


async def dashboard(ws: websockets.ClientConnection) -> tuple[set[str], str, str]:
    """Read until the Dashboard's three plots and its marker have come: the plots' uuids, the marker's."""
    zstd = zstandard.ZstdDecompressor()
    plots: set[str] = set()
    marker: tuple[str, str] | None = None
    async with asyncio.timeout(PANEL_TIMEOUT_S):
        while len(plots) < 3 or marker is None:
            for message in await next_messages(ws, zstd):
                if message.get("type") == "GuiUplotMessage":
                    plots.add(message["uuid"])
                found = MARKER.search(str(message.get("props", {}).get("content", "")))
                if found:
                    marker = (found.group(1), found.group(2))
    return plots, *marker


async def plot_updates(ws: websockets.ClientConnection, plots: set[str], seconds: float) -> int:
    """How many times the plots' data came in `seconds`."""
    zstd = zstandard.ZstdDecompressor()
    count = 0
    until = time.monotonic() + seconds
    while (left := until - time.monotonic()) > 0:
        try:
            messages = await asyncio.wait_for(next_messages(ws, zstd), left)
        except TimeoutError:
            break
        for message in messages:
            update = message.get("type") == "GuiUpdateMessage" and message.get("uuid") in plots
            if update and "data" in message.get("updates", {}):
                count += 1
    return count


async def settle(ws: websockets.ClientConnection, plots: set[str]) -> None:
    """Read until the plots' data has not come for SETTLE_S (what was already on its way when the page
    said the tab left); fails after SETTLE_TIMEOUT_S."""
    deadline = time.monotonic() + SETTLE_TIMEOUT_S
    while await plot_updates(ws, plots, SETTLE_S) > 0:
        assert time.monotonic() < deadline, f"the plots still came {SETTLE_TIMEOUT_S} s after the tab left"


def test_the_plots_are_sent_while_the_tab_is_shown_and_not_before_or_after(page: PendantUI) -> None:
    async def browse() -> tuple[int, int, int]:
        ws = await open_viewer(page.server.get_port())
        try:
            plots, came, went = await dashboard(ws)
            on_jog_tab = await plot_updates(ws, plots, WATCH_S)
            await ws.send(click_message(came))  # the marker came into view: the Dashboard tab opened
            shown = await plot_updates(ws, plots, WATCH_S)
            await ws.send(click_message(went))  # and left: another tab opened
            await settle(ws, plots)
            left = await plot_updates(ws, plots, WATCH_S)
            return on_jog_tab, shown, left
        finally:
            await ws.close()

    on_jog_tab, shown, left = asyncio.run(browse())
    assert on_jog_tab == 0, f"the plots were sent {on_jog_tab} times to a page on another tab"
    assert shown >= 2, f"the Dashboard shown: its plots came {shown} times in {WATCH_S} s (2 refreshes/s)"
    assert left == 0, f"the plots were sent {left} times after the page left the tab"
