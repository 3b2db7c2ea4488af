"""A stop wins until the operator lets go (issue 22), in a real Chromium: J1+ held by mouse, finger or Space
while a Freeze comes from the API, from another browser's Freeze button or from Esc. The arm must stay still
while the button stays down, and move again once it is released and pressed again."""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator

import pytest
from playwright.sync_api import Browser, Page

from tests.support.jog_measure import PoseSampler, button_centre, open_as_operator, touch, wait_idle
from tests.support.launchers import Pendant
from tests.support.waiting import wait_until

# Real-time figures (the arm still for 1.5 s while held): run alone, after the rest.
pytestmark = pytest.mark.measures

# The jog must have turned J1 this far before the stop comes, within JOG_WITHIN_S of the press (at the pad's
# speed it takes about 0.8 s, more while the page is still confirming its first frames on a loaded machine).
MOVED_DEG = 1.0
JOG_WITHIN_S = 5.0
STOP_SETTLE_S = 0.3  # the stop has reached the controller by then
STILL_WINDOW_S = 1.5  # J1 measured this long while the button stays down after the stop
STILL_TOL_DEG = 0.01  # J1 changed by less than this over the window: still
NOTICE_TIMEOUT_MS = 5_000
DEADMAN_PRESSES = 3  # presses again after a release, when the deadman (not the stop) cut the one before


@pytest.fixture(scope="module")
def operator(browser: Browser, pendant: Pendant) -> Iterator[Page]:
    page = browser.new_page(viewport={"width": 1024, "height": 768}, has_touch=True)
    open_as_operator(page, pendant.ui_url)
    yield page
    page.close()


@pytest.fixture(scope="module")
def bystander(browser: Browser, pendant: Pendant, operator: Page) -> Iterator[Page]:
    """Another browser (a viewer: any browser may press Freeze)."""
    context = browser.new_context(viewport={"width": 1024, "height": 768})
    page = context.new_page()
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=90_000)
    yield page
    context.close()


def press(page: Page, gesture: str) -> Callable[[], None]:
    """Put J1+ down by `gesture`; the function that lets it go."""
    if gesture == "mouse":
        page.mouse.move(*button_centre(page, "J1+"))
        page.mouse.down()
        return lambda: page.mouse.up()
    if gesture == "finger":
        cdp = page.context.new_cdp_session(page)
        x, y = button_centre(page, "J1+")
        touch(cdp, "touchStart", x, y)
        return lambda: touch(cdp, "touchEnd", x, y)
    page.get_by_role("button", name="J1+", exact=True).focus()
    page.keyboard.down("Space")
    return lambda: page.keyboard.up("Space")


def j1(pendant: Pendant) -> float:
    return pendant.pose()[0]


def jogged(pendant: Pendant, start: float) -> bool:
    """J1 turned MOVED_DEG from `start` within JOG_WITHIN_S (the button held all the while)."""
    try:
        wait_until(lambda: j1(pendant) > start + MOVED_DEG, JOG_WITHIN_S, "J1's jog")
    except TimeoutError:
        return False
    return True


# Each gesture meets each source once over the three runs (all nine would triple the time for little more).
@pytest.mark.parametrize(
    ("gesture", "source"), [("mouse", "api"), ("finger", "other browser"), ("Space", "Esc")]
)
def test_a_freeze_ends_the_held_jog_until_the_button_is_released_and_pressed_again(
    operator: Page, bystander: Page, pendant: Pendant, gesture: str, source: str
) -> None:
    wait_idle(pendant.api)
    start = j1(pendant)
    release = press(operator, gesture)
    try:
        assert jogged(pendant, start), f"holding J1+ by {gesture} did not jog"
        if source == "api":
            pendant.api.put("/freeze").raise_for_status()
        elif source == "other browser":
            bystander.get_by_role("button", name="Freeze").click()
        else:
            operator.keyboard.press("Escape")
        time.sleep(STOP_SETTLE_S)
        sampler = PoseSampler(pendant.api)
        sampler.start()
        time.sleep(STILL_WINDOW_S)
        window = [angle for _, angle in sampler.stop(released_at=0.0, settle_s=0.0).samples]
        # The page was confirming the hold all along (it did not let go by itself): the stop held.
        assert operator.evaluate("document.documentElement.dataset.jogging !== undefined")
        assert max(window) - min(window) < STILL_TOL_DEG, f"J1 moved after the {source} Freeze"
        # Named in the log and on the page. On a loaded machine the page may stall and the deadman stop the
        # press just before the Freeze: then that is the cause (the stop holds all the same).
        logged = pendant.api.get("/pendant/events", params={"text": "Jog J1+ stopped", "limit": 1}).json()
        cause = logged["events"][0]["message"].removeprefix("Jog J1+ stopped: ") if logged["events"] else ""
        assert cause.startswith(("Freeze", "deadman")), logged
        operator.get_by_text(f"J1+ stopped: {cause}", exact=False).first.wait_for(timeout=NOTICE_TIMEOUT_MS)
    finally:
        release()
    for attempt in range(1, DEADMAN_PRESSES + 1):
        wait_idle(pendant.api)
        again, since = j1(pendant), latest_event_id(pendant)
        release = press(operator, gesture)
        try:
            if jogged(pendant, again):
                break
            # On a loaded machine the page's confirmations can pause past the 200 ms deadman, which then
            # rightly stops the new press: that is not the stop under test, so the press is made again.
            cut = deadman_cut_since(pendant, since)
            assert cut and attempt < DEADMAN_PRESSES, (
                f"released and pressed again, J1+ did not jog (press {attempt}, deadman cut: {cut})"
            )
        finally:
            release()


def latest_event_id(pendant: Pendant) -> int:
    events = pendant.api.get("/pendant/events", params={"limit": 1}).json()["events"]
    return int(events[0]["id"]) if events else 0


def deadman_cut_since(pendant: Pendant, since: int) -> bool:
    """Whether the event log says the deadman stopped a jog after event `since`."""
    logged = pendant.api.get("/pendant/events", params={"text": "deadman", "limit": 5}).json()["events"]
    return any(int(event["id"]) > since for event in logged)
