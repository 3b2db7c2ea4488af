"""The keyboard follows the layout: from the start of the page Tab goes to Freeze first, then the banner's
buttons when one shows, then down the panel (status, control, the tab bar, the active tab's controls top to
bottom); every stop is a control the operator can see, none hidden off-screen, under the pinned Freeze, or
behind the 3D view."""

from __future__ import annotations

from collections.abc import Iterator
from itertools import pairwise
from typing import Any

import pytest

from tests.support.jog_measure import open_as_operator
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

TABS = ("Jog", "Target", "Program", "Cell", "IO", "Robot", "Simulator", "Dashboard")
MAX_STOPS = 150  # more than any tab has: the walk ends when focus leaves the page
ROW_TOLERANCE_PX = 4.0  # controls of one row (a slider and its number) sit a pixel or two apart
SETTLE_MS = 800  # a tab's controls drawn and the accessibility pass run (150 ms after the DOM settles)
UI_TIMEOUT_MS = 30_000
BACK_STOPS = 40  # Shift+Tab from the end of the Program tab, back up past a screen's height of controls

# What has focus: its accessible name, where it is in the panel's content (scroll offsets added, so a
# scrolled panel compares with an unscrolled one), and whether the operator can see it: in the viewport,
# and the thing drawn at its centre is itself (not the pinned Freeze or banner, not the 3D canvas).
FOCUSED_JS = """() => {
  const e = document.activeElement;
  if (e === null || e === document.body || e === document.documentElement) return null;
  const r = e.getBoundingClientRect();
  let y = r.top;
  for (let box = e.parentElement; box !== null; box = box.parentElement) y += box.scrollTop;
  const name = (e.getAttribute("aria-label") || e.innerText || e.getAttribute("title") || "").trim();
  const hit = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
  const seen = r.width > 0 && r.height > 0 && r.bottom > 0 && r.right > 0 && r.top < innerHeight
    && r.left < innerWidth && hit !== null && (hit === e || e.contains(hit) || hit.contains(e));
  return {name: name.split("\\n")[0], role: e.getAttribute("role") || e.tagName.toLowerCase(),
          x: r.left, y, seen, drawn: hit === null ? "nothing" : hit.tagName.toLowerCase()};
}"""


@pytest.fixture
def desk_page(browser: Any, pendant: Pendant) -> Iterator[Any]:
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    page = context.new_page()
    open_as_operator(page, pendant.ui_url)
    # A newcomer's tabs are built one after another (issue 37): under load the walk of the first tab once
    # began with only Jog and Target in the tab bar.
    for tab in TABS:
        page.get_by_role("tab", name=tab).wait_for(timeout=UI_TIMEOUT_MS)
    yield page
    context.close()
    pendant.api.put("/sim/reset").raise_for_status()


def from_the_start(page: Any) -> None:
    """Nothing focused, as when the page has just loaded (or the operator clicked the 3D view)."""
    page.evaluate("() => document.activeElement && document.activeElement.blur()")


def walk(page: Any, key: str = "Tab", limit: int = MAX_STOPS) -> list[dict[str, Any]]:
    """Press `key` until focus leaves the page (or comes round again): every stop, in order."""
    stops: list[dict[str, Any]] = []
    for _ in range(limit):
        page.keyboard.press(key)
        stop = page.evaluate(FOCUSED_JS)
        if stop is None or (stops and stop == stops[0]):
            break
        stops.append(stop)
    return stops


def open_tab(page: Any, name: str) -> None:
    page.get_by_role("tab", name=name).click()
    page.wait_for_timeout(SETTLE_MS)


def unseen(stops: list[dict[str, Any]]) -> list[str]:
    return [f"{s['name']!r} ({s['role']}, under a {s['drawn']})" for s in stops if not s["seen"]]


def upwards(stops: list[dict[str, Any]]) -> list[str]:
    """Each next stop not above the one before it (in the panel's content)."""
    return [
        f"{a['name']!r} at {a['y']:.0f} px, then {b['name']!r} at {b['y']:.0f} px"
        for a, b in pairwise(stops)
        if b["y"] < a["y"] - ROW_TOLERANCE_PX
    ]


def tab_bar(stops: list[dict[str, Any]]) -> list[int]:
    return [k for k, s in enumerate(stops) if s["role"] == "tab"]


def test_freeze_then_the_banner_then_the_tab_bar_then_the_jog_pad(desk_page: Any, pendant: Pendant) -> None:
    page = desk_page
    pendant.api.put("/sim/fault/error").raise_for_status()
    page.get_by_role("button", name="Recover", exact=True).wait_for(timeout=UI_TIMEOUT_MS)
    page.wait_for_timeout(SETTLE_MS)
    from_the_start(page)
    stops = walk(page)
    names = [s["name"] for s in stops]
    assert names[:2] == ["Freeze", "Recover"], names[:6]  # the way out right after the stop
    tabs = tab_bar(stops)
    assert [names[k] for k in tabs] == list(TABS) and tabs == list(range(tabs[0], tabs[0] + len(TABS)))
    # then the active tab, from its top: the jog pad (one stop), then the teach row
    assert names[tabs[-1] + 1 : tabs[-1] + 3] == ["J1-", "Record"]
    assert "Protective stop" not in names  # hidden while Recover shows: no stop for a hidden button
    assert upwards(stops) == []
    assert unseen(stops) == []


def test_every_tab_is_walked_top_to_bottom_after_freeze_and_the_tab_bar(desk_page: Any) -> None:
    page = desk_page
    found = {}
    for tab in TABS:
        open_tab(page, tab)
        from_the_start(page)
        stops = walk(page)
        names = [s["name"] for s in stops]
        tabs = tab_bar(stops)
        found[tab] = {
            "first": names[0],
            "tab bar": [names[k] for k in tabs],
            "controls after it": len(stops) > tabs[-1] + 1 if tabs else False,
            "upwards": upwards(stops),
            "unseen": unseen(stops),
        }
    expected = {
        "first": "Freeze",
        "tab bar": list(TABS),
        "controls after it": True,
        "upwards": [],
        "unseen": [],
    }
    assert found == {tab: expected for tab in TABS}


def test_shift_tab_back_up_a_scrolled_tab_never_hides_under_freeze(desk_page: Any) -> None:
    page = desk_page
    open_tab(page, "Program")
    from_the_start(page)
    down = walk(page)
    back = walk(page, "Shift+Tab", BACK_STOPS)
    assert [s["name"] for s in back] == [s["name"] for s in reversed(down)][:BACK_STOPS]  # the same way back
    assert unseen(back) == []


MAX_TEACH_TABS = 5  # issue 33: Record and Run within 5 Tabs of the jog pad
# Which control has focus: a jog button by its name, a teach row button by its part ("record", "run").
FOCUSED_CONTROL_JS = """() => {
  const e = document.activeElement;
  return e === null ? null : (e.dataset.teach || e.getAttribute("aria-label") || e.tagName.toLowerCase());
}"""


def focused(page: Any) -> str | None:
    return page.evaluate(FOCUSED_CONTROL_JS)


def tabs_to(page: Any, wanted: str) -> int:
    """Tabs pressed until `wanted` has focus (MAX_STOPS + 1 if it never does)."""
    for count in range(1, MAX_STOPS + 1):
        page.keyboard.press("Tab")
        if focused(page) == wanted:
            return count
    return MAX_STOPS + 1


def test_record_and_run_are_a_few_tabs_from_the_jog_pad_and_arrows_move_inside_it(desk_page: Any) -> None:
    page = desk_page
    pad = page.get_by_role("button", name="J1-", exact=True)
    counts = {}
    for wanted in ("record", "run"):
        pad.focus()
        counts[wanted] = tabs_to(page, wanted)
    assert counts["record"] <= MAX_TEACH_TABS and counts["run"] <= MAX_TEACH_TABS, counts
    # The arrows move along the pad; the Tab stop goes with them, and a Tab leaves the pad for Record.
    pad.focus()
    visited = []
    for key in ("ArrowRight", "ArrowDown", "ArrowDown", "ArrowLeft", "ArrowUp", "End", "Home"):
        page.keyboard.press(key)
        visited.append(focused(page))
    assert visited == ["J1+", "J2+", "J3+", "J3-", "J2-", "J6+", "J1-"]
    page.keyboard.press("ArrowDown")
    page.keyboard.press("Tab")
    assert focused(page) == "record"
    page.keyboard.press("Shift+Tab")
    assert focused(page) == "J2-"  # back into the pad where it was left
