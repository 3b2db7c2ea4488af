"""An operator at a real page who counts what they do: every click or tap, every jog held, every key, and
every scroll they need to reach a control that is not in view (docs/screens.md: "Teaching in one place")."""

from __future__ import annotations

import contextlib
import time
from collections.abc import Callable
from typing import Any

from tests.support.jog_measure import button_centre, settled, touch
from tests.support.waiting import wait_until

SCREENS = {"desk": (1400, 900), "tablet": (768, 1024), "phone": (390, 844)}
TOUCH_SCREENS = ("tablet", "phone")
MOVING_WITHIN_S = 15.0  # a press to the arm moving, on a loaded 2-core machine
MOVING_POLL_S = 0.05


def open_screen(browser: Any, url: str, screen: str) -> Any:
    """The pendant at `screen`'s size, with touch on the tablet and the phone, its panels built."""
    width, height = SCREENS[screen]
    page = browser.new_page(viewport={"width": width, "height": height}, has_touch=screen in TOUCH_SCREENS)
    page.goto(url)
    page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=90_000)  # the last tab built
    return page


def in_view(locator: Any) -> bool:
    """Wholly inside the window and not hidden under the panel's edge: what a person can press as it is."""
    return bool(
        locator.evaluate(
            """(el) => {
                const r = el.getBoundingClientRect();
                if (r.width === 0 || r.top < 0 || r.left < 0) return false;
                if (r.bottom > innerHeight || r.right > innerWidth) return false;
                const hit = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);
                return hit !== null && (hit === el || el.contains(hit));
            }"""
        )
    )


class Operator:
    """Presses controls the way the screen is used (mouse on a desk, a finger on a touch screen) and counts
    each action; a control out of view costs a scroll first (one more action)."""

    def __init__(self, page: Any, *, touch: bool) -> None:
        self.page = page
        self.touch = touch
        self.cdp = page.context.new_cdp_session(page) if touch else None
        self.actions = 0
        self.scrolls = 0
        self.log: list[str] = []

    def _reach(self, locator: Any, what: str) -> None:
        if not in_view(locator):
            locator.scroll_into_view_if_needed()
            self.scrolls += 1
            self._count(f"scroll to {what}")

    def _count(self, what: str) -> None:
        self.actions += 1
        self.log.append(what)

    def press(self, locator: Any, what: str) -> None:
        """A click (or a tap)."""
        self._reach(locator, what)
        if self.touch:
            locator.tap()
        else:
            locator.click()
        self._count(what)

    def hold(self, label: str, seconds: float, moving: Callable[[], bool] = lambda: True) -> None:
        """A jog button held for `seconds` once the arm is seen `moving` (as a person holds on until it
        does: a loaded machine takes a moment to start it; at most MOVING_WITHIN_S), then let go."""
        button = self.page.get_by_role("button", name=label, exact=True)
        self._reach(button, label)
        # Held where the button stays, as a person watching it does: a press at coordinates misses a button
        # that is still moving (test_closing_the_tab's misses, 4 Dec). Likely the same: a clean clone's
        # tablet case whose J2+ hold never moved the arm (P2 recorded on P1).
        settled(self.page, label)
        x, y = button_centre(self.page, label)
        if self.cdp is not None:
            touch(self.cdp, "touchStart", x, y)
            self._hold_on(moving, seconds)
            touch(self.cdp, "touchEnd", x, y)
        else:
            self.page.mouse.move(x, y)
            self.page.mouse.down()
            self._hold_on(moving, seconds)
            self.page.mouse.up()
        self._count(f"hold {label}")

    @staticmethod
    def _hold_on(moving: Callable[[], bool], seconds: float) -> None:
        # Still not moving at the deadline: let go all the same (the test then finds the waypoint not moved).
        with contextlib.suppress(TimeoutError):
            wait_until(moving, MOVING_WITHIN_S, "the arm moving", MOVING_POLL_S)
        time.sleep(seconds)
