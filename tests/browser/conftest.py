"""A real pendant process (simulator + UI + API on loopback) and a real Chromium driven by Playwright.
Every test in this folder is marked `browser` (`pytest -m "not browser"` leaves them out)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, Playwright

from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.launchers import Pendant
from tests.support.launchers import running_pendant_ui as running_pendant

ARTIFACTS = Path(__file__).resolve().parents[2] / "test-artifacts"
HERE = Path(__file__).resolve().parent

__all__ = ["ARTIFACTS", "CHROMIUM", "CHROMIUM_ARGS", "Pendant", "running_pendant"]


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if HERE in Path(item.path).parents:
            item.add_marker(pytest.mark.browser)


@pytest.fixture(scope="module")
def pendant() -> Iterator[Pendant]:
    with running_pendant() as served:
        yield served


# Module-scoped, not session-scoped: sync Playwright keeps an asyncio loop running in the test thread while
# it is open, and a later non-browser test on the same xdist worker calling asyncio.run() then fails.
@pytest.fixture(scope="module")
def playwright() -> Iterator[Playwright]:
    """Playwright's driver, once per module: its sync API allows one at a time in a thread, so a module
    that needs a Chromium of its own launches it from this one."""
    from playwright.sync_api import sync_playwright

    if not Path(CHROMIUM).exists():
        pytest.fail(f"Chromium not found at {CHROMIUM}: install Debian's chromium (apt-get install chromium)")
    with sync_playwright() as driver:
        yield driver


@pytest.fixture(scope="module")
def browser(playwright: Playwright) -> Iterator[Browser]:
    """One Chromium for the module: every test opens its own page or context in it."""
    browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    yield browser
    browser.close()


@pytest.fixture
def page(browser: Browser, pendant: Pendant) -> Iterator[Page]:
    ARTIFACTS.mkdir(exist_ok=True)
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=30_000)
    yield page
    page.close()
