"""What loading the page costs Chromium, lit by lights (the default) or by viser's HDR environment map
(`--environment-map city`, viser's own default look) (issue 36: the browser tests load the page ~100 times;
issue 37: a room of newcomers).

Two real `pendant` processes side by side and Debian's Chromium (software WebGL, as the browser tests run
it). Each round opens one page per variant in turn, at 1400x900, so both see the same load (printed), and
reports for the first `--window` seconds after the navigation starts:

  CPU       Chromium's CPU seconds by kind of process (the GPU process draws WebGL in software)
  Freeze    seconds until the Freeze button is on screen
  view      seconds until the 3D view has shown a frame at full opacity (viser's client keeps the view at
            5 % opacity until its HDR map is decoded and prefiltered, one long frame in software WebGL)

Run: .venv/bin/python benchmarks/page_load.py [--rounds 3] [--window 15]
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
from collections import defaultdict
from pathlib import Path

from playwright.sync_api import Browser, sync_playwright

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.idle_page import chromium_cpu
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.launchers import running_pendant_ui

VARIANTS = {"lights (default)": (), "environment map city": ("--environment-map", "city")}
PAGE_TIMEOUT_MS = 60_000
POLL_S = 0.1
# The view has shown a frame (view_frames.js counts them) and no canvas of the page is faded.
VIEW_SHOWN = """() => window.__pendant !== undefined && window.__pendant.viewFrames !== undefined &&
  window.__pendant.viewFrames() > 0 &&
  [...document.querySelectorAll("canvas")].every((c) => getComputedStyle(c).opacity === "1")"""


def load_once(browser: Browser, url: str, window_s: float) -> tuple[dict[str, float], float, float]:
    """CPU seconds by kind over the window, seconds to Freeze, and seconds to the view shown (inf: not in
    the window)."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    page = context.new_page()
    before = chromium_cpu()
    started = time.monotonic()
    page.goto(url)
    page.get_by_role("button", name="Freeze").wait_for(timeout=PAGE_TIMEOUT_MS)
    freeze_s = time.monotonic() - started
    view_s = float("inf")
    while (now := time.monotonic()) - started < window_s:
        if view_s == float("inf") and page.evaluate(VIEW_SHOWN):
            view_s = now - started
        time.sleep(POLL_S)
    after = chromium_cpu()
    context.close()
    return {kind: after[kind] - before.get(kind, 0.0) for kind in after}, freeze_s, view_s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--window", type=float, default=15.0, help="seconds measured from each navigation")
    args = parser.parse_args()
    results: dict[str, list[tuple[dict[str, float], float, float]]] = defaultdict(list)
    with contextlib.ExitStack() as stack:
        urls = {
            name: stack.enter_context(running_pendant_ui(*flags)).ui_url for name, flags in VARIANTS.items()
        }
        playwright = stack.enter_context(sync_playwright())
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for _ in range(args.rounds):
            for name, url in urls.items():
                results[name].append(load_once(browser, url, args.window))
        browser.close()
    print(f"load average {os.getloadavg()[0]:.1f}; one page load, 1400x900, the first {args.window:g} s")
    for name, rounds in results.items():
        for spent, freeze_s, view_s in rounds:
            kinds = ", ".join(f"{kind} {value:.1f}" for kind, value in sorted(spent.items()) if value >= 0.05)
            print(
                f"  {name:22s} {sum(spent.values()):5.1f} CPU-s ({kinds}); Freeze at {freeze_s:.1f} s; "
                f"view shown at {view_s:.1f} s"
            )


if __name__ == "__main__":
    main()
