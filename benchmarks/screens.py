"""What fits where: the panel at the four screen sizes the pendant is checked at (docs/screens.md).

A real `pendant` process (simulator) and Debian's chromium. Per screen size: where the panel sits and how
wide it is, the 3D view's width beside it, Freeze's box, the Dashboard's motor table against the panel's
width, and per tab how far the panel scrolls (its content height over the visible height: 1.0 = no scroll).
tests/browser/test_screen_fit.py checks the same page: Freeze on screen, nothing scrolling sideways.

Run: .venv/bin/python benchmarks/screens.py
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.browser.conftest import CHROMIUM, CHROMIUM_ARGS, running_pendant

SCREENS = {
    "desktop": (1400, 900),
    "tablet-landscape": (1024, 768),
    "tablet-portrait": (768, 1024),
    "phone": (390, 844),
}
MEASURE = """(freeze) => {
    const panel = freeze.closest('.mantine-ScrollArea-viewport');
    const p = panel.getBoundingClientRect(), f = freeze.getBoundingClientRect();
    const canvas = document.querySelector('canvas').getBoundingClientRect();
    const table = document.querySelector('#motor-table');
    return {
        panel: [p.left, p.top, p.width, p.height], freeze: [f.left, f.top, f.right, f.bottom],
        view: canvas.width, table: table ? table.getBoundingClientRect().width : null,
        pages: panel.scrollHeight / panel.clientHeight, wide: panel.scrollWidth > panel.clientWidth,
    };
}"""


def main() -> None:
    from playwright.sync_api import sync_playwright

    rows = []
    with running_pendant() as pendant, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for screen, (width, height) in SCREENS.items():
            page = browser.new_page(
                viewport={"width": width, "height": height}, has_touch=screen != "desktop"
            )
            page.goto(pendant.ui_url)
            freeze = page.get_by_role("button", name="Freeze", exact=True)
            freeze.wait_for(timeout=60_000)
            page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=60_000)
            page.wait_for_timeout(1_500)  # the docked panel settles
            pages = {}
            for tab in [name.strip() for name in page.get_by_role("tab").all_inner_texts()]:
                page.get_by_role("tab", name=tab, exact=True).click()
                if tab == "Dashboard":
                    page.locator("#motor-table").wait_for(timeout=10_000)
                page.wait_for_timeout(300)
                state = freeze.evaluate(MEASURE)
                pages[tab] = f"{state['pages']:.1f}" + (" WIDE" if state["wide"] else "")
                if tab == "Dashboard":
                    dashboard = state
            page.close()
            rows.append((screen, width, height, dashboard, pages))
        browser.close()

    print(
        "| screen | panel (x, width) px | 3D view width px | Freeze (left-right, top-bottom) px "
        "| motor table / panel width px |"
    )
    print("|---|---|---|---|---|")
    for screen, width, height, d, _ in rows:
        x, y, w, _height = d["panel"]
        fl, ft, fr, fb = d["freeze"]
        print(
            f"| {screen} {width}x{height} | {x:.0f}, {w:.0f} (top {y:.0f}) | {d['view']:.0f} "
            f"| {fl:.0f}-{fr:.0f}, {ft:.0f}-{fb:.0f} | {d['table']:.0f} / {w:.0f} |"
        )
    tabs = list(rows[0][4])
    print()
    print("Panel content height / visible height per tab (1.0: no scrolling):")
    print("| screen | " + " | ".join(tabs) + " |")
    print("|---|" + "---|" * len(tabs))
    for screen, _, _, _, pages in rows:
        print(f"| {screen} | " + " | ".join(pages.get(tab, "-") for tab in tabs) + " |")


if __name__ == "__main__":
    main()
