"""What the browser tests (tests/browser) share: where they leave screenshots, and the steps several of them
take on a pendant's page or through its API (waiting for the arm, moving it, taking control, picking from a
dropdown)."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from playwright.sync_api import Page

from tests.support.launchers import REPO_ROOT, Pendant

ARTIFACTS = REPO_ROOT / "test-artifacts"  # screenshots of every page a browser test saw

# Poses and pace of the program tests (test_program_page.py and those built on it).
POSE_A_DEG = [25.0, -90.0, 90.0, -90.0, -90.0, 0.0]
POSE_B_DEG = [-25.0, -80.0, 80.0, -90.0, -90.0, 0.0]
AWAY_DEG = [0.0, -100.0, 100.0, -90.0, -90.0, 0.0]
MOVE_SPEED_PERCENT = 60
ANGLE_TOL_DEG = 0.01
UI_TIMEOUT_MS = 15_000
RUN_TIMEOUT_S = 60.0
POLL_S = 0.02  # a real process on a real clock: the test watches it through the API

SETTLE_S = 0.6
MOVE_TIMEOUT_S = 30.0
CONTROL_TIMEOUT_S = 60.0
PAGE_THROTTLE_FLUSH_MS = 100  # longer than viser's page-side 50 ms send throttle (see `sent`)


PANELS_TIMEOUT_MS = 90_000  # a loaded 2-core machine


def open_tab(page: Page, name: str) -> None:
    """Open the tab `name` as a person does, once the page has its whole panel (the "Loading the panels"
    note under Freeze gone): a tab clicked while the builder was still adding tabs stayed on the Jog tab in
    a clean-clone run (the Dashboard's legend then never filled in). The tab must then be the open one."""
    page.get_by_text("Loading the panels").wait_for(state="detached", timeout=PANELS_TIMEOUT_MS)
    tab = page.get_by_role("tab", name=name, exact=True)
    tab.click()
    tab.and_(page.locator('[aria-selected="true"]')).wait_for(timeout=UI_TIMEOUT_MS)


def wait_idle(pendant: Pendant, timeout_s: float = MOVE_TIMEOUT_S) -> None:
    deadline = time.monotonic() + timeout_s
    while pendant.status() != "IDLE":
        assert time.monotonic() < deadline, "the arm did not come to rest"
        time.sleep(0.1)


def move_to(pendant: Pendant, angles: list[float]) -> None:
    """Put the arm somewhere through the API (as jogging would) and wait until it is there."""
    pendant.api.put("/pose", params={"speed": MOVE_SPEED_PERCENT}, json={"angles": angles}).raise_for_status()
    deadline = time.monotonic() + RUN_TIMEOUT_S
    while pendant.status() != "IDLE" or not np.allclose(pendant.pose(), angles, atol=ANGLE_TOL_DEG):
        assert time.monotonic() < deadline, "the arm did not get there"
        time.sleep(POLL_S)


def obstacles(pendant: Pendant) -> list[dict[str, Any]]:
    return pendant.api.get("/environment").json()


def sent(page: Page) -> None:
    """Wait until the page has sent the last edit to the pendant.

    viser's page sends every control's edits through one 50 ms throttle that keeps only the latest message:
    a second control edited inside that window (stretched to a whole frame while software WebGL draws)
    replaces the first one's pending edit, which never reaches the pendant although the field shows it.
    A page timer longer than the throttle's fires after it (timers fire in order), so the edit has gone.
    """
    page.evaluate(f"() => new Promise(done => setTimeout(done, {PAGE_THROTTLE_FLUSH_MS}))")


def take_control(page: Page) -> None:
    """On loopback the first page gets control; a loaded machine may take a while to say so (and to draw
    the page): take it if the page shows the button meanwhile, then start once the page draws."""
    mine = page.get_by_text("You have control").first
    take = page.get_by_role("button", name="Take control")
    deadline = time.monotonic() + CONTROL_TIMEOUT_S
    while not mine.is_visible():
        assert time.monotonic() < deadline, "this page never got control"
        if take.is_visible():
            take.click()
        time.sleep(0.2)
    page.evaluate("new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)))")


def choose(page: Page, current: str, option: str) -> None:
    """Pick `option` in the visible dropdown now showing `current`."""
    page.locator(f"input[value='{current}']:visible").first.click()
    page.get_by_role("option", name=option, exact=True).click()
