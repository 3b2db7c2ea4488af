"""/docs and /redoc render in a real browser with no network beyond the pendant (issue #16, finding 9: they
loaded Swagger UI from a CDN and were blank offline). Every request to another host is aborted and counted."""

from __future__ import annotations

from urllib.parse import urlsplit

import pytest
from playwright.sync_api import Browser, Route

from tests.support.launchers import Pendant
from tests.support.shared_pendants import NOT_REAL_TIME

# Not about real time: the shared pendant's simulator runs faster (tests/browser/conftest.py).
pytestmark = pytest.mark.time_scale(NOT_REAL_TIME)

RENDER_TIMEOUT_MS = 30_000
SHOWN = "Setting a new arm pose"
REDOCLY_FOOTER_LOGO = "https://cdn.redoc.ly/redoc/logo-mini.svg"


@pytest.fixture(scope="module")
def api_url(pendant: Pendant) -> str:
    """The API port of the shared pendant: the same API app as `pendant --no-ui` serves."""
    return str(pendant.api.base_url).rstrip("/")


@pytest.mark.parametrize("page_path", ["/docs", "/redoc"])
def test_the_api_documentation_renders_offline(browser: Browser, api_url: str, page_path: str) -> None:
    page = browser.new_page()
    elsewhere: list[str] = []

    def offline(route: Route) -> None:
        if urlsplit(route.request.url).hostname == "127.0.0.1":
            route.continue_()
        else:
            elsewhere.append(route.request.url)
            route.abort()

    page.route("**/*", offline)
    try:
        page.goto(api_url + page_path)
        # An operation of the API, as each page shows it: Swagger UI's summary line, ReDoc's heading.
        operation = page.get_by_text(SHOWN, exact=True).first
        if page_path == "/redoc":
            operation = page.get_by_role("heading", name=SHOWN)
        operation.wait_for(timeout=RENDER_TIMEOUT_MS)
    finally:
        page.close()
    # ReDoc's bundle shows its maker's logo in its footer ("API docs by Redocly") from the maker's CDN:
    # offline, that one image is missing and nothing else. Anything more would be a page needing the network.
    assert [url for url in elsewhere if url != REDOCLY_FOOTER_LOGO] == []
