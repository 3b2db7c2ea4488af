"""What fits where: the panel at the four screen sizes the pendant is checked at (docs/screens.md).

A real `pendant` process (simulator) and Debian's chromium. Per screen size: where the panel sits and how
big it is, the 3D view beside or above it, the arm's box on screen (its meshes projected with the page's
camera: tests/support/arm_view.py), Freeze's box, the Dashboard's motor table against the panel's width, and
per tab how far the panel scrolls (its content height over the visible height: 1.0 = no scroll).
tests/browser/test_screen_fit.py checks the same page: Freeze on screen, nothing scrolling sideways;
tests/browser/test_phone_layout.py: the arm in view, clear of the panel.

Run: .venv/bin/python benchmarks/screens.py [--screenshots docs/screenshots]
(--screenshots: the README's desk, tablet and phone pictures, the Jog tab at 1400x900, 768x1024, 390x844.)
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.arm_view import arm_on_screen, close_notifications, drawn_dark_pixels
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.launchers import running_pendant_ui

SCREENS = {
    "desktop": (1400, 900),
    "tablet-landscape": (1024, 768),
    "tablet-portrait": (768, 1024),
    "phone": (390, 844),
}
DRAWN_DARK_PIXELS = 20  # the arm's joint caps in its box: the view has drawn it
SCREENSHOTS = {"desk": "desktop", "tablet": "tablet-portrait", "phone": "phone"}
MEASURE = """(freeze) => {
    const panel = freeze.closest('.mantine-ScrollArea-viewport');
    const p = panel.getBoundingClientRect(), f = freeze.getBoundingClientRect();
    const canvas = document.querySelector('canvas').getBoundingClientRect();
    const table = document.querySelector('#motor-table');
    return {
        panel: [p.left, p.top, p.width, p.height], freeze: [f.left, f.top, f.right, f.bottom],
        view: [canvas.width, canvas.height], table: table ? table.getBoundingClientRect().width : null,
        pages: panel.scrollHeight / panel.clientHeight, wide: panel.scrollWidth > panel.clientWidth,
    };
}"""


def main() -> None:
    from playwright.sync_api import sync_playwright

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--screenshots", type=Path, help="write desk/tablet/phone.png here")
    args = parser.parse_args()
    rows = []
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for screen, (width, height) in SCREENS.items():
            page = browser.new_page(
                viewport={"width": width, "height": height}, has_touch=screen != "desktop"
            )
            page.goto(pendant.ui_url + "?dpr=1")  # the software renderer at full resolution
            freeze = page.get_by_role("button", name="Freeze", exact=True)
            freeze.wait_for(timeout=60_000)
            page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=60_000)
            page.wait_for_timeout(1_500)  # the docked panel settles
            close_notifications(page)
            arm = arm_on_screen(page)
            # The view shows the arm a frame or two after its meshes arrive (the phone's first screenshot
            # was taken before: a white view).
            drawn_dark_pixels(page, arm["arm"], at_least=DRAWN_DARK_PIXELS)
            for name, shown in SCREENSHOTS.items():
                if args.screenshots is not None and shown == screen:
                    args.screenshots.mkdir(parents=True, exist_ok=True)
                    page.screenshot(path=str(args.screenshots / f"{name}.png"))
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
            rows.append((screen, width, height, dashboard, pages, arm))
        browser.close()

    print(
        "| screen | panel (left, top, width x height) px | 3D view px | arm (left-right, top-bottom) px "
        "| Freeze (left-right, top-bottom) px | motor table / panel width px |"
    )
    print("|---|---|---|---|---|---|")
    for screen, width, height, d, _, arm in rows:
        x, y, w, h = d["panel"]
        fl, ft, fr, fb = d["freeze"]
        al, at, ar, ab = arm["arm"]
        print(
            f"| {screen} {width}x{height} | {x:.0f}, {y:.0f}, {w:.0f} x {h:.0f} "
            f"| {d['view'][0]:.0f} x {d['view'][1]:.0f} | {al:.0f}-{ar:.0f}, {at:.0f}-{ab:.0f} "
            f"| {fl:.0f}-{fr:.0f}, {ft:.0f}-{fb:.0f} | {d['table']:.0f} / {w:.0f} |"
        )
    tabs = list(rows[0][4])
    print()
    print("Panel content height / visible height per tab (1.0: no scrolling):")
    print("| screen | " + " | ".join(tabs) + " |")
    print("|---|" + "---|" * len(tabs))
    for screen, _, _, _, pages, _ in rows:
        print(f"| {screen} | " + " | ".join(pages.get(tab, "-") for tab in tabs) + " |")


if __name__ == "__main__":
    main()
