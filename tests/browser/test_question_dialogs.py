"""Questions that cannot be missed: New and Load over unsaved changes, and Delete file, ask in a dialog that
takes the keyboard focus and covers the panel; nothing changes until the operator answers Yes, and Cancel
leaves everything as it was. (Before: an inline Yes/Cancel line in the Files folder, easy to miss, so the
next Records went into the old program.)"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Page

from tests.support.browser_pages import ARTIFACTS, open_tab
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant_ui as running_pendant

UI_TIMEOUT_MS = 20_000
FOCUS_IN_DIALOG = "() => document.querySelector('[role=dialog]')?.contains(document.activeElement) === true"


@pytest.fixture(scope="module")
def pendant(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Pendant]:
    programs = tmp_path_factory.mktemp("programs")
    with running_pendant("--programs", str(programs)) as served:
        served.programs = programs
        yield served


def dialog(page: Any) -> Any:
    return page.get_by_role("dialog")


def ask(page: Any, option: str, question: str) -> Any:
    """Press a Files button; the dialog that opens, with `question`, holding the focus."""
    page.get_by_role("button", name=option, exact=True).click()
    asked = dialog(page)
    asked.get_by_text(question).wait_for(timeout=UI_TIMEOUT_MS)
    page.wait_for_function(
        FOCUS_IN_DIALOG,
        timeout=UI_TIMEOUT_MS,
    )
    return asked


def file_is(page: Any, path: Path, *, there: bool) -> None:
    for _ in range(UI_TIMEOUT_MS // 100):
        if path.exists() == there:
            return
        page.wait_for_timeout(100)
    raise AssertionError(f"{path.name} {'never saved' if there else 'not deleted'}")


def steps_are(page: Any, pendant: Pendant, count: int) -> None:
    """The program being edited (its autosave) has `count` steps."""
    autosave = pendant.programs / ".autosave.json"
    for _ in range(UI_TIMEOUT_MS // 100):
        if len(json.loads(autosave.read_text())["program"]["steps"]) == count:
            return
        page.wait_for_timeout(100)
    raise AssertionError(f"the program does not have {count} steps: {autosave.read_text()[:500]}")


def steps_listed(page: Any, text: str) -> None:
    page.get_by_text(text).first.wait_for(timeout=UI_TIMEOUT_MS)


def test_new_load_and_delete_ask_in_a_dialog_that_takes_the_focus(page: Page, pendant: Pendant) -> None:
    open_tab(page, "Program")  # once the page has its whole panel (a tab clicked sooner can stay unopened)
    page.get_by_role("button", name="Record", exact=True).click()
    steps_listed(page, "1. Move J to P1 @ 20%")
    page.get_by_role("textbox", name="Save as name").fill("keep")
    page.get_by_role("button", name="Save as", exact=True).click()
    file_is(page, pendant.programs / "keep.json", there=True)
    page.get_by_role("button", name="Record", exact=True).click()
    steps_listed(page, "2. Move J to P2 @ 20%")  # unsaved now

    asked = ask(page, "New", "Discard the unsaved changes")
    page.screenshot(path=str(ARTIFACTS / "question-dialog.png"))
    asked.get_by_role("button", name="Cancel", exact=True).click()
    dialog(page).wait_for(state="detached", timeout=UI_TIMEOUT_MS)
    steps_listed(page, "2. Move J to P2 @ 20%")  # Cancel: all there
    steps_are(page, pendant, 2)

    asked = ask(page, "Load", "Discard the unsaved changes")
    asked.get_by_role("button", name="Cancel", exact=True).click()
    dialog(page).wait_for(state="detached", timeout=UI_TIMEOUT_MS)

    asked = ask(page, "New", "Discard the unsaved changes")
    asked.get_by_role("button", name="Yes", exact=True).click()
    dialog(page).wait_for(state="detached", timeout=UI_TIMEOUT_MS)
    steps_are(page, pendant, 0)  # Yes: a new, empty program

    assert (pendant.programs / "keep.json").exists()
    asked = ask(page, "Delete file", "Delete the file keep.json?")
    asked.get_by_role("button", name="Yes", exact=True).click()
    dialog(page).wait_for(state="detached", timeout=UI_TIMEOUT_MS)
    file_is(page, pendant.programs / "keep.json", there=False)
