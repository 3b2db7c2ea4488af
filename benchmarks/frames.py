"""The page's main thread while the arm moves, the 3D view drawn in the page or off it (issue 35).

A real `pendant` process and Debian's Chromium (software WebGL, as the browser tests run it). For each screen
size (1400x900, 768x1024) and each way of drawing the view, one page at a time, alternating, so all see the
same load (printed): a 10 s mouse hold on J1 (the arm moves), during which the page's long tasks are recorded
(PerformanceObserver 'longtask': how long a press or release can wait), the frames the view drew, and
whether the deadman cut the hold; then release -> arm still (from when the driver sent the release).

  in the page   ?view=inline: viser's canvas composited by the page (main at the start of issue 35)
  worker        the default: three.js draws into an OffscreenCanvas read back with no wait, a worker shows it
  hidden        ?view=inline with the canvas hidden (display: none): the floor, the page without its 3D view

Targets (issue 35, load <= 3): long tasks p90 <= 60 ms and none over 150 ms; no deadman cut in a 10 s hold at
load <= 4; release -> still p99 <= 120 ms; >= 10 frames a second at 1400x900.

Run: .venv/bin/python benchmarks/frames.py [--rounds 2] [--hold 10]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.jog_measure import ensure_operator, mouse_hold
from tests.support.launchers import running_pendant_ui

VARIANTS = {"in the page": "?view=inline", "worker": "", "hidden": "?view=inline"}
SIZES = ((1400, 900), (768, 1024))
# Before the page's own scripts: long tasks, and the frames drawn (three.js clears once per frame).
_PROBE = """
window.__lt = [];
new PerformanceObserver((list) => { for (const e of list.getEntries()) window.__lt.push(e.duration); })
  .observe({ type: "longtask" });
window.__clears = 0;
const clear = WebGL2RenderingContext.prototype.clear;
WebGL2RenderingContext.prototype.clear = function (mask) {
  window.__clears += 1;
  return clear.call(this, mask);
};
"""
_DRAWN = "() => window.__clears > 0"
SETTLE_S = 3.0
_HIDE_VIEW = "document.addEventListener('DOMContentLoaded', () => document.head.insertAdjacentHTML("
_HIDE_VIEW += "'beforeend', '<style>canvas { display: none !important; }</style>'));"


def pct(values: list[float], q: float) -> float:
    ms = sorted(values)
    return ms[min(len(ms) - 1, round(q * (len(ms) - 1)))] if ms else 0.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--hold", type=float, default=10.0, help="seconds each hold lasts")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    keys = [(size, name) for size in SIZES for name in VARIANTS]
    tasks: dict[tuple, list[float]] = {k: [] for k in keys}
    fps: dict[tuple, list[float]] = {k: [] for k in keys}
    cuts: dict[tuple, int] = dict.fromkeys(keys, 0)
    stops: dict[tuple, list[float]] = {k: [] for k in keys}
    moved: dict[tuple, list[float]] = {k: [] for k in keys}
    loads: list[float] = []
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for i in range(args.rounds):
            for size, name in keys:
                page = browser.new_page(viewport={"width": size[0], "height": size[1]})
                page.add_init_script(_PROBE)
                if name == "hidden":
                    page.add_init_script(_HIDE_VIEW)
                page.goto(pendant.ui_url + VARIANTS[name])
                ensure_operator(page)
                page.wait_for_function(_DRAWN, timeout=90_000)  # its first frame (shaders compiled)
                time.sleep(SETTLE_S)
                page.evaluate("window.__lt.length = 0; window.__clears = 0")
                loads.append(os.getloadavg()[0])
                timeline = mouse_hold(page, pendant.api, "J1+" if i % 2 == 0 else "J1-", args.hold)
                tasks[size, name] += page.evaluate("window.__lt.slice()")
                fps[size, name].append(page.evaluate("window.__clears") / (args.hold + 0.6))
                cuts[size, name] += timeline.stalls_while_held()
                stops[size, name].append(timeline.stop_after_release_s() * 1000)
                moved[size, name].append(timeline.moved_deg)
                page.close()
        browser.close()
    print(f"load average (1 min) during the holds: {min(loads):.1f}-{max(loads):.1f}")
    for size, name in keys:
        lt, over = tasks[size, name], sum(t > 150 for t in tasks[size, name])
        print(
            f"{size[0]}x{size[1]} {name:12s} long tasks n={len(lt):3d} p50 {pct(lt, 0.5):4.0f} ms "
            f"p90 {pct(lt, 0.9):4.0f} ms max {pct(lt, 1.0):4.0f} ms, >150 ms: {over:2d} | "
            f"{statistics.mean(fps[size, name]):4.1f} frames/s | deadman cuts {cuts[size, name]} in "
            f"{args.rounds} x {args.hold:.0f} s | release -> still p99 {pct(stops[size, name], 0.99):4.0f} ms"
            f" | J1 moved {min(moved[size, name]):.1f}-{max(moved[size, name]):.1f} deg"
        )


if __name__ == "__main__":
    main()
