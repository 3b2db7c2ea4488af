"""The page's typed boxes (pendant/ui/kit/typed_field.py) in a real browser: found by their row's label (the
page's accessibility script names each box after it), typed as a person types, committed with Enter."""

from __future__ import annotations

from playwright.sync_api import Locator, Page


def typed_box(page: Page, label: str) -> Locator:
    """The visible text box labelled `label` ("J1 °", "Speed %", "Position mm")."""
    return page.locator(f'input[aria-label="{label}"]:visible').first


def type_into(page: Page, label: str, text: str, *, delay_ms: float = 0.0, commit: str = "Enter") -> Locator:
    """Replace the box's text with `text`, one key every `delay_ms`, then commit it (Enter, or Tab)."""
    box = typed_box(page, label)
    box.click()
    box.press("ControlOrMeta+a")
    if text:
        box.press_sequentially(text, delay=delay_ms)
    else:
        box.press("Backspace")
    box.press(commit)
    return box
