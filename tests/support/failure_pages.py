"""What a failed browser test's pages showed when it failed: each open page's screenshot (in
test-artifacts/failures/) and, in the test's report, the words of any dialog or banner on it. CI keeps only
the printed output, and a dialog over a button (a question the test did not expect) reads there as a plain
click time-out."""

from __future__ import annotations

import contextlib
import re
from pathlib import Path

from playwright.sync_api import Browser, Error, Page

from tests.support.browser_pages import ARTIFACTS

FAILURES = ARTIFACTS / "failures"
LOOK_MS = 3_000  # a page that does not answer in this long is said to be stuck, not waited for
SHOWN = "#recovery-banner, [role=dialog]"
MAX_CHARS = 600  # characters of each dialog or banner in the report


def describe_pages(browser: Browser, test_name: str) -> str:
    """One paragraph per open page: its URL, its screenshot's file, and what its dialogs and banner say."""
    FAILURES.mkdir(parents=True, exist_ok=True)
    stem = re.sub(r"[^\w.-]+", "_", test_name)[:120]
    pages = [page for context in browser.contexts for page in context.pages]
    described = [_describe(page, FAILURES / f"{stem}-{n}.png") for n, page in enumerate(pages, 1)]
    return "\n".join(described) or "no page open"


def _describe(page: Page, png: Path) -> str:
    lines = [f"page {page.url}"]
    with contextlib.suppress(Error):
        page.screenshot(path=str(png), timeout=LOOK_MS)
        lines.append(f"  screenshot: {png}")
    try:
        shown = page.locator(SHOWN).all()
        for box in shown:
            if box.is_visible():
                words = " ".join(box.inner_text(timeout=LOOK_MS).split())
                lines.append(f"  {box.get_attribute('role') or 'banner'}: {words[:MAX_CHARS]}")
    except Error as error:
        lines.append(f"  (not readable: {str(error).splitlines()[0]})")
    return "\n".join(lines)
