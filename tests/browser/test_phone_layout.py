"""The arm in view beside (or above) the panel at a desktop, an upright tablet and a phone, measured as the
operator sees it: the arm's meshes projected with the page's own camera lie wholly inside the 3D view, clear
of the panel, nothing is on top of them, the arm is really drawn there, and Freeze is wholly on screen.

On a phone (<= 480 px wide) the panel is a full-width bottom sheet under the view; its grab bar resizes it
(a tap switches between the usual and a small sheet, a drag sets any size in between) and the arm stays
framed above it; viser's tap on the panel's title row no longer folds Freeze away; the tabs sit on one row
that scrolls sideways inside itself only. (Freeze at every scroll position of every tab: test_screen_fit.py.)
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from playwright.sync_api import Browser

from tests.support.arm_view import arm_on_screen, close_notifications, drawn_dark_pixels, overlap
from tests.support.browser_pages import ARTIFACTS
from tests.support.jog_measure import on_top, settled
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

SCREENS = {"desktop": (1400, 900), "tablet-portrait": (768, 1024), "phone": (390, 844)}
PX_TOL = 1
MIN_DARK_PIXELS = 40  # the joint caps of the arm at its smallest (a phone): a few hundred on a desktop
# The camera frames the arm and the reach around it (the same framing as a desktop): at least this share of
# the view's height, however the sheet is sized.
MIN_ARM_SHARE = 0.25
PHONE = SCREENS["phone"]


def open_page(browser: Any, pendant: Pendant, screen: tuple[int, int]) -> Any:
    page = browser.new_page(viewport={"width": screen[0], "height": screen[1]}, has_touch=True)
    page.goto(pendant.ui_url)
    page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=60_000)  # the last tab built
    settled(page, "Freeze")
    close_notifications(page)
    return page


@pytest.fixture
def phone(browser, pendant: Pendant) -> Iterator[Any]:  # type: ignore[no-untyped-def]
    page = open_page(browser, pendant, PHONE)
    yield page
    page.close()


def check_arm_in_view(page: Any, where: str) -> dict[str, Any]:
    state = arm_on_screen(page)
    left, top, right, bottom = state["arm"]
    c_left, c_top, c_right, c_bottom = state["canvas"]
    assert left >= c_left - PX_TOL and top >= c_top - PX_TOL, f"arm cut off the view in {where}: {state}"
    assert right <= c_right + PX_TOL and bottom <= c_bottom + PX_TOL, f"arm cut off in {where}: {state}"
    assert right <= state["width"] and bottom <= state["height"], f"arm off screen in {where}: {state}"
    assert not overlap(state["arm"], state["panel"]), f"the panel covers the arm in {where}: {state}"
    assert not overlap(state["arm"], state["bar"]), f"the grab bar covers the arm in {where}: {state}"
    assert state["covered"] == [], f"something over the arm in {where}: {state['covered']}"
    share = (bottom - top) / (c_bottom - c_top)
    assert share >= MIN_ARM_SHARE, f"the arm is {share:.0%} of the view's height in {where}: {state['arm']}"
    drawn = drawn_dark_pixels(page, state["arm"], MIN_DARK_PIXELS)
    assert drawn >= MIN_DARK_PIXELS, f"the arm is not drawn in {where} ({drawn} dark pixels)"
    f_left, f_top, f_right, f_bottom = state["freeze"]
    assert f_left >= 0 and f_top >= 0 and f_right <= state["width"] and f_bottom <= state["height"], where
    assert on_top(page, "Freeze"), f"Freeze covered in {where}"
    return state


@pytest.mark.parametrize("screen", SCREENS)
def test_the_whole_arm_in_view_clear_of_the_panel_and_freeze_on_screen(
    browser: Browser, pendant: Pendant, screen: str
) -> None:
    width, height = SCREENS[screen]
    page = open_page(browser, pendant, (width, height))
    try:
        state = check_arm_in_view(page, f"{width}x{height}")
        page.screenshot(path=str(ARTIFACTS / f"arm-and-panel-{width}x{height}.png"))
        panel = state["panel"]
        if screen == "phone":  # a bottom sheet across the whole width, the view above it
            assert panel[0] <= PX_TOL and panel[2] >= width - PX_TOL, f"the sheet is not full width: {panel}"
            assert state["canvas"][3] <= state["bar"][1] + PX_TOL <= panel[1] + PX_TOL, state
            assert 0.5 * height <= panel[3] - panel[1] <= 0.65 * height, f"sheet height: {panel}"
        else:  # docked beside the view, as before
            assert state["canvas"][2] <= panel[0] + PX_TOL, state
    finally:
        page.close()


def sheet_top(page: Any) -> float:
    return float(arm_on_screen(page)["panel"][1])


def test_the_grab_bar_resizes_the_sheet_and_the_arm_stays_in_view(phone: Any) -> None:
    usual = sheet_top(phone)
    bar = phone.get_by_role("button", name="Make the panel smaller")
    bar.tap()
    phone.wait_for_timeout(500)
    small = check_arm_in_view(phone, "a small sheet")
    assert small["panel"][1] > usual + 0.15 * PHONE[1], (usual, small["panel"])
    phone.get_by_role("button", name="Make the panel larger").tap()
    phone.wait_for_timeout(500)
    assert abs(sheet_top(phone) - usual) <= PX_TOL
    # A drag of the bar 80 px up makes the sheet 80 px taller (the mouse drags as a finger would; the usual
    # sheet is 64 % of the screen, the tallest 75 %).
    box = bar.bounding_box()
    assert box is not None
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    phone.mouse.move(x, y)
    phone.mouse.down()
    for step in range(1, 11):
        phone.mouse.move(x, y - 8 * step)
    phone.mouse.up()
    phone.wait_for_timeout(500)
    assert abs(sheet_top(phone) - (usual - 80)) <= 2, (usual, sheet_top(phone))
    check_arm_in_view(phone, "a tall sheet")


def test_tapping_the_panel_title_row_never_folds_freeze_away(phone: Any) -> None:
    """viser folded its whole bottom panel (Freeze with it) on a tap of the title row; now the tap only
    switches the sheet's size, and Freeze stays."""
    state = arm_on_screen(phone)
    title = phone.get_by_text("PULSE pendant", exact=True).first
    title.tap()
    phone.wait_for_timeout(800)
    assert on_top(phone, "Freeze"), "Freeze folded away"
    after = arm_on_screen(phone)
    assert after["panel"][1] > state["panel"][1], "the tap did not make the sheet smaller"
    assert phone.get_by_role("tab", name="Jog", exact=True).is_visible()


def test_the_tabs_sit_on_one_row_that_alone_scrolls_sideways(phone: Any) -> None:
    tabs = phone.get_by_role("tab")
    tops = {round(tabs.nth(k).bounding_box()["y"]) for k in range(tabs.count())}
    assert len(tops) == 1, f"tabs on {len(tops)} rows: {sorted(tops)}"
    last = phone.get_by_role("tab", name="Dashboard", exact=True)
    last.click()
    phone.locator("#motor-table").wait_for(timeout=10_000)
    inside = last.evaluate(
        """(tab) => {
            const t = tab.getBoundingClientRect(), l = tab.parentElement.getBoundingClientRect();
            const page = document.scrollingElement || document.documentElement;
            return { tab: t.left >= l.left - 1 && t.right <= l.right + 1,
                     listScrolled: tab.parentElement.scrollLeft,
                     pageWide: page.scrollWidth > page.clientWidth };
        }"""
    )
    assert inside["tab"] and inside["listScrolled"] > 0, inside
    assert not inside["pageWide"], "the page scrolls sideways"
    assert on_top(phone, "Freeze")
