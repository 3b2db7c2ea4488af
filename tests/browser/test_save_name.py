"""Save on a program that has no file yet, in a real browser: the pendant asks for the name with the cursor
already in the name box, the operator types it straight away, and the next Save writes the file."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from playwright.sync_api import Browser

from tests.support.browser_pages import ARTIFACTS
from tests.support.jog_measure import open_as_operator
from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

UI_TIMEOUT_MS = 30_000
SAVE_TIMEOUT_S = 10.0
POLL_S = 0.1


@pytest.fixture(scope="module")
def programs(pendant: Pendant) -> Path:
    """The pendant's programs folder (empty: a shared pendant is handed out only as fresh as a new one)."""
    return pendant.programs


def test_save_of_an_unnamed_program_puts_the_cursor_in_the_name_box(
    browser: Browser, pendant: Pendant, programs: Path
) -> None:
    page = browser.new_page(viewport={"width": 1024, "height": 768})
    try:
        open_as_operator(page, pendant.ui_url)
        page.get_by_role("tab", name="Program", exact=True).click()
        page.get_by_role("button", name="Record", exact=True).click()
        page.get_by_text("Move J to P1").first.wait_for(timeout=UI_TIMEOUT_MS)

        page.get_by_role("button", name="Save", exact=True).click()
        page.get_by_text("Name this program: type a name, then press Save.").wait_for(timeout=UI_TIMEOUT_MS)
        # The text box in the row labelled "Save as name" (viser's label is not tied to its input).
        label = page.get_by_text("Save as name", exact=True)
        name_box = label.locator("xpath=ancestor::div[.//input][1]//input").first
        page.wait_for_function("(box) => document.activeElement === box", arg=name_box.element_handle())
        page.screenshot(path=str(ARTIFACTS / "save-asks-for-a-name.png"))
        assert list(programs.glob("[!.]*.json")) == [], "saved before it had a name"

        page.keyboard.type("first job")  # straight into the focused box: no click on it first
        page.keyboard.press("Enter")
        page.get_by_role("button", name="Save", exact=True).click()
        saved = programs / "first job.json"
        deadline = time.monotonic() + SAVE_TIMEOUT_S
        while not saved.exists():
            assert time.monotonic() < deadline, "the second Save wrote no file"
            time.sleep(POLL_S)
        assert [step["kind"] for step in json.loads(saved.read_text())["steps"]] == ["move"]
        page.get_by_text("first job.json").first.wait_for(timeout=UI_TIMEOUT_MS)  # the tab says so
    finally:
        page.close()
