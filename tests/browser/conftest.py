"""A real pendant process (simulator + UI + API on loopback) and a real Chromium driven by Playwright.
Every test in this folder is marked `browser` (`pytest -m "not browser"` leaves them out).

Shared, so the folder runs in minutes: one Chromium per pytest process (per xdist worker), every test in a
fresh context (a page of its own: cookies, storage, viewport); one pendant per set of flags, reset between
modules and replaced when it cannot be (tests/support/shared_pendants.py). A module marked
`time_scale(K)` gets a pendant whose simulator runs K times the wall clock (its tests are not about real
time); `measures` tests never ask for one."""

from __future__ import annotations

from collections.abc import Generator, Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, Playwright

from tests.support.browser_pages import ARTIFACTS
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.failure_pages import describe_pages
from tests.support.launchers import Pendant
from tests.support.rerun_report import PAGES_SECTION, PENDANT_SECTION
from tests.support.shared_pendants import SharedPendants, shared_pendants

HERE = Path(__file__).resolve().parent
PAGE_LOAD_TIMEOUT_MS = 90_000  # a page drawn in software WebGL on a loaded 2-core machine


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark this folder's tests `browser`, and run them after every other test of the same run: the
    session's Playwright keeps an asyncio loop running in the test thread from its first browser test on,
    and a later test calling asyncio.run() would fail (`make test` runs this folder in pytests of its own)."""
    ours = [item for item in items if HERE in Path(item.path).parents]
    for item in ours:
        item.add_marker(pytest.mark.browser)
    others = [item for item in items if HERE not in Path(item.path).parents]
    items[:] = others + ours


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(
    item: pytest.Item, call: pytest.CallInfo[None]
) -> Generator[None, pytest.TestReport, pytest.TestReport]:
    """A failed test's report says what its pages showed (tests/support/failure_pages.py) and what its
    pendant printed last."""
    report: pytest.TestReport = yield
    funcargs = getattr(item, "funcargs", {})
    browser, pendant = funcargs.get("browser"), funcargs.get("pendant")
    if report.when == "call" and report.failed and isinstance(browser, Browser):
        report.sections.append((PAGES_SECTION, describe_pages(browser, item.name)))
    if report.when == "call" and report.failed and isinstance(pendant, Pendant):
        report.sections.append((PENDANT_SECTION, pendant.said() or "(nothing)"))
    return report


@pytest.fixture(scope="session")
def playwright() -> Iterator[Playwright]:
    """Playwright's driver, once per pytest process: its sync API allows one at a time in a thread, so a
    module that needs a Chromium of its own (other flags) launches it from this one."""
    from playwright.sync_api import sync_playwright

    if not Path(CHROMIUM).exists():
        pytest.fail(f"Chromium not found at {CHROMIUM}: install Debian's chromium (apt-get install chromium)")
    with sync_playwright() as driver:
        yield driver


@pytest.fixture(scope="session")
def browser(playwright: Playwright) -> Iterator[Browser]:
    """One Chromium for the pytest process: every test opens its own context (browser.new_page() or
    new_context()), closed at its end."""
    browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    yield browser
    browser.close()


@pytest.fixture(scope="session")
def pendant_pool() -> Iterator[SharedPendants]:
    with shared_pendants() as pool:
        yield pool


def time_scale_flags(request: pytest.FixtureRequest) -> tuple[str, ...]:
    marker = request.node.get_closest_marker("time_scale")
    if marker is None:
        return ()
    return ("--time-scale", str(float(marker.args[0])))


@pytest.fixture(scope="module")
def pendant(request: pytest.FixtureRequest, pendant_pool: SharedPendants) -> Iterator[Pendant]:
    """The module's pendant: a shared one, as fresh as a new one (its programs folder in `.programs`, its
    data folder in `.data`); not handed out again if a test of the module failed."""
    failed = request.session.testsfailed
    served = pendant_pool.get(*time_scale_flags(request))
    yield served
    if request.session.testsfailed > failed:
        pendant_pool.taint(served)


@pytest.fixture
def page(browser: Browser, pendant: Pendant) -> Iterator[Page]:
    ARTIFACTS.mkdir(exist_ok=True)
    page = browser.new_page(viewport={"width": 1400, "height": 900})
    page.goto(pendant.ui_url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=PAGE_LOAD_TIMEOUT_MS)
    yield page
    page.context.close()
