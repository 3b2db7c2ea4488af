"""What one open page costs Chromium while the arm is at rest, by way of drawing the 3D view (issue 36: the
suite's browser tests keep pages open, most of that time with the arm still; issue 37: a room of viewers).

A real `pendant` process and Debian's Chromium (software WebGL, as the browser tests run it). For each way of
drawing the view, one page at a time at 1400x900, its panels built and settled: the CPU each kind of Chromium
process spends over a window (the GPU process, which draws WebGL in software; the page's renderer; the rest),
in cores, and the frames three.js drew a second (viser's client draws on demand, with a heartbeat frame a
second). Every variant is measured in turn, `--rounds` times, so all see the same load (printed).

  worker        the default (issue 35): three.js draws into an OffscreenCanvas read back with no wait
  in the page   ?view=inline: viser's canvas composited by the page
  hidden        ?view=none: three.js runs but draws nothing, the floor
  ..., viser's heartbeat   ?heartbeat_ms=1000: a frame every second at rest, as viser asks (the pendant's
                page asks every 5 s: rest_frames.js)

Run: .venv/bin/python benchmarks/idle_page.py [--rounds 2] [--window 10]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections import defaultdict
from pathlib import Path

from playwright.sync_api import Page, sync_playwright

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.cpu_report import CHROMIUM as CHROMIUM_NAME
from tests.support.cpu_report import descendants
from tests.support.launchers import running_pendant_ui

VARIANTS = {
    "worker": "",
    "worker, viser's heartbeat": "?heartbeat_ms=1000",
    "in the page": "?view=inline",
    "in the page, viser's heartbeat": "?view=inline&heartbeat_ms=1000",
    "hidden": "?view=none",
}
SETTLE_S = 5.0  # after the last tab is built: the load's own frames are over
PAGE_TIMEOUT_MS = 60_000
# Before the page's own scripts: three.js clears once per frame.
COUNT_FRAMES = """
window.__clears = 0;
const clear = WebGL2RenderingContext.prototype.clear;
WebGL2RenderingContext.prototype.clear = function (...args) {
  window.__clears++;
  return clear.apply(this, args);
};
"""


def chromium_cpu() -> dict[str, float]:
    """CPU seconds so far of this process's Chromium (its descendants), summed by process --type
    (gpu-process, renderer, ...; "browser" for the one without)."""
    spent: dict[str, float] = defaultdict(float)
    for pid, process in descendants().items():
        if process.command != CHROMIUM_NAME:
            continue
        try:  # a child of Chromium's writes its arguments as one string, spaces between them
            arguments = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").split()
        except OSError:
            continue  # ended meanwhile
        kind = next((a.decode()[7:] for a in arguments if a.startswith(b"--type=")), "browser")
        spent[kind] += process.cpu_s
    return spent


def measure(page: Page, window_s: float) -> tuple[dict[str, float], float]:
    """Cores by kind of Chromium process over `window_s`, and frames drawn a second."""
    before, frames = chromium_cpu(), page.evaluate("window.__clears")
    started = time.monotonic()
    page.wait_for_timeout(window_s * 1000)
    elapsed = time.monotonic() - started
    after, drawn = chromium_cpu(), page.evaluate("window.__clears")
    cores = {kind: (after[kind] - before.get(kind, 0.0)) / elapsed for kind in after}
    return cores, (drawn - frames) / elapsed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--window", type=float, default=10.0, help="seconds measured per page")
    args = parser.parse_args()
    results: dict[str, list[tuple[dict[str, float], float]]] = defaultdict(list)
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for _ in range(args.rounds):
            for variant, query in VARIANTS.items():
                context = browser.new_context(viewport={"width": 1400, "height": 900})
                context.add_init_script(COUNT_FRAMES)
                page = context.new_page()
                page.goto(pendant.ui_url + query)
                page.get_by_role("tab", name="Dashboard", exact=True).wait_for(timeout=PAGE_TIMEOUT_MS)
                page.wait_for_timeout(SETTLE_S * 1000)
                results[variant].append(measure(page, args.window))
                context.close()
        browser.close()
    print(f"load average {os.getloadavg()[0]:.1f}; one page at rest, 1400x900, {args.window:g} s each")
    for variant, rounds in results.items():
        for cores, frames in rounds:
            shown = sorted((kind, value) for kind, value in cores.items() if value >= 0.005)
            kinds = ", ".join(f"{kind} {value:.2f}" for kind, value in shown)
            print(f"  {variant:31s} {sum(cores.values()):.2f} cores ({kinds}); {frames:.1f} frames/s")


if __name__ == "__main__":
    main()
