"""Every tab at the four screen sizes the pendant is used at: Freeze wholly on screen at every scroll position
of the panel, and nothing scrolls sideways (the panel, its scrolling ancestors, the page), even with long
unbreakable names on show (the programs folder, the tool) and the Dashboard's motor table filled in.

One pendant for the module and one page per screen size, every tab in that page.
"""

from __future__ import annotations

import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser
from playwright.sync_api import Error as PlaywrightError

from tests.support.browser_pages import ARTIFACTS
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant_ui as running_pendant

SCREENS = {
    "desktop": (1400, 900),
    "tablet-landscape": (1024, 768),
    "tablet-portrait": (768, 1024),
    "phone": (390, 844),
}
SCROLL_FRACTIONS = (0.0, 0.3, 0.6, 1.0)
# Names with no place to break them at a word: the Program tab shows the folder's path, the status and the
# event log the tool's name.
LONG_FOLDER = "cell-7-welding-station-programs-" * 3
LONG_TOOL = "vacuum_gripper_" * 6
SCROLL_SETTLE_MS = 150
PX_TOL = 1  # sub-pixel rounding of boxes

# The panel's state at this scroll position, read in one go: Freeze's box, the viewport, and every box from
# Freeze's scrolling viewport up to the document whose content is wider than its visible width.
MEASURE = """(freeze) => {
    const panel = freeze.closest('.mantine-ScrollArea-viewport');
    const wide = [];
    for (let box = panel; box !== null; box = box.parentElement) {
        if (box.scrollWidth > box.clientWidth) {
            wide.push(`${box.tagName}.${box.className} ${box.scrollWidth} > ${box.clientWidth}`);
        }
    }
    const page = document.scrollingElement || document.documentElement;
    if (page.scrollWidth > page.clientWidth) wide.push(`document ${page.scrollWidth} > ${page.clientWidth}`);
    const r = freeze.getBoundingClientRect();
    const hit = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
    return {
        freeze: [r.left, r.top, r.right, r.bottom], width: innerWidth, height: innerHeight,
        covered: hit === null || !freeze.contains(hit), wide,
        scrollTop: panel.scrollTop, scrollMax: panel.scrollHeight - panel.clientHeight,
    };
}"""
SCROLL_TO = """(freeze, fraction) => {
    const panel = freeze.closest('.mantine-ScrollArea-viewport');
    panel.scrollTop = fraction * (panel.scrollHeight - panel.clientHeight);
}"""


@pytest.fixture(scope="module")
def pendant() -> Iterator[Pendant]:
    with tempfile.TemporaryDirectory(prefix="pendant-programs-") as folder:
        programs = Path(folder) / LONG_FOLDER
        with running_pendant("--programs", str(programs)) as served:
            origin = {"x": 0.0, "y": 0.0, "z": 0.0}
            tool = {
                "name": LONG_TOOL,
                "radius": 0.0,
                "point": origin,
                "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
            }
            served.api.post("/tool", json=tool).raise_for_status()
            yield served


@pytest.mark.parametrize("screen", SCREENS)
def test_freeze_on_screen_and_no_sideways_scroll_in_any_tab(
    browser: Browser, pendant: Pendant, screen: str
) -> None:
    width, height = SCREENS[screen]
    page = browser.new_page(viewport={"width": width, "height": height}, has_touch=screen != "desktop")
    try:
        page.goto(pendant.ui_url)
        freeze = page.get_by_role("button", name="Freeze", exact=True)
        freeze.wait_for(timeout=60_000)
        page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=60_000)  # the last tab built
        tabs = [name.strip() for name in page.get_by_role("tab").all_inner_texts()]
        assert {"Jog", "Program", "Dashboard"} <= set(tabs), tabs
        for tab in tabs:
            page.get_by_role("tab", name=tab, exact=True).click()
            if tab == "Dashboard":  # the table fills in at the next refresh (5 Hz)
                page.locator("#motor-table").wait_for(timeout=10_000)
            if tab == "Program":
                page.get_by_text(LONG_FOLDER[:40]).first.wait_for(timeout=10_000)
            for fraction in SCROLL_FRACTIONS:
                freeze.evaluate(SCROLL_TO, fraction)
                page.wait_for_timeout(SCROLL_SETTLE_MS)
                state = freeze.evaluate(MEASURE)
                where = f"{tab} scrolled to {fraction:.0%} at {width}x{height}"
                left, top, right, bottom = state["freeze"]
                assert left >= -PX_TOL and top >= -PX_TOL, f"Freeze off screen in {where}: {state['freeze']}"
                assert right <= width + PX_TOL and bottom <= height + PX_TOL, (
                    f"Freeze off screen in {where}: {state['freeze']}"
                )
                assert not state["covered"], f"Freeze covered in {where}"
                assert state["wide"] == [], f"scrolls sideways in {where}: {state['wide']}"
            if tab == "Dashboard":  # the reported case: the J6 column cut off at the panel's right edge
                j6 = page.get_by_role("columnheader", name="J6", exact=True)
                box = header_box(j6)  # the table is redrawn 5 times a second: its header is replaced
                page.screenshot(path=str(ARTIFACTS / f"screen-fit-dashboard-{width}x{height}.png"))
                panel = freeze.bounding_box()
                assert box is not None and panel is not None
                assert box["x"] + box["width"] <= panel["x"] + panel["width"] + PX_TOL, (box, panel)
    finally:
        page.close()


def header_box(header: Any) -> Any:
    """The header's box once scrolled into view; the motor table is redrawn while we look (5 Hz), so a header
    replaced between the scroll and the reading is looked up again."""
    for _ in range(10):
        try:
            header.scroll_into_view_if_needed(timeout=5000)
            box = header.bounding_box(timeout=5000)
            if box is not None:
                return box
        except PlaywrightError:
            pass
    raise AssertionError("the J6 header never stayed on the page long enough to be measured")
