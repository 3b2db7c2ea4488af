"""Jogging: how fast the arm stops after the operator lets go, and how fast a press shows in the browser.

1. Deadman stop latency (wall clock, in-process simulator on the real clock): confirm a continuous jog at
   20 Hz, stop confirming, and time from the last confirmation until the arm is frozen. The deadman is
   200 ms, so the target is 200 ms plus a few ms of watchdog period.
2. Press -> first pose change seen in the browser: a real `pendant` process and Debian's chromium; the page
   timestamps the pointerdown on "J1+" and the arrival on the page of the first message after it that moves
   one of the arm's links (status and dashboard updates do not count). Target: p50 <= 100 ms. (Painting it
   adds one frame: Chromium renders WebGL in software here, at about 15-20 frames/s on 2 loaded cores.)
   For comparison, the server's own part: jog request -> the moved arm handed to viser, in-process.

3. Hold J1 for 1.0 s in a real Chromium (software WebGL) at 1400x900, by mouse and by finger (CDP touch
   events), against the same motion sent to the API (PUT /pose at 10 %, PUT /freeze 1.0 s later): degrees
   moved, press -> first motion, release -> arm still, stalls inside one press; a swipe that starts on a
   jog button; and the page's frame time while the arm moves (requestAnimationFrame intervals, and how
   long the main thread is blocked at a time), viser's own rendering against the pendant's.

   Three release times: from when the driver sent it, from the browser's stamp of the input (event.timeStamp)
   and from when the page's handler ran. For a finger they differ most: CDP's emulated touch
   (Input.dispatchTouchEvent) is forwarded to the page only once the page has presented a frame (a Chrome
   trace shows the browser waiting on the renderer's WidgetCompositor before it forwards the touchEnd), and
   its stamp is the driver's; with software WebGL that wait is 150-900 ms, which a real touchscreen does not
   add. The mouse's stamp is the browser's own.

4. The tablet (768x1024, touch enabled): hold J1 1.0 s by API, mouse and finger, alternating in one run so
   all three see the same load (printed beside the figures), and where each press and release spends its
   time: press sent -> handled by the page -> hold handed to the worker (touch: the press-or-swipe check)
   -> first motion; release sent -> handled by the page -> release handed to the worker -> arm still.

Run: .venv/bin/python benchmarks/jog.py [--trials 20] [--holds 5] [--only-browser | --only-tablet]
"""

from __future__ import annotations

import argparse
import itertools
import statistics
import sys
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pendant.controller import MotionStatus
from pendant.jog import JogFrame, Jogger, JogRequest
from pendant.sim import MonotonicClock, SimController
from tests.support.chromium import CHROMIUM, CHROMIUM_ARGS
from tests.support.launchers import running_pendant_ui
from tests.support.waiting import wait_until

if TYPE_CHECKING:
    import numpy as np
    from playwright.sync_api import Page

    from tests.support.jog_measure import Timeline

CONFIRM_PERIOD_S = 0.05
# Small, because Chromium paints WebGL in software here: a bigger canvas only measures the painting.
VIEWPORT = (960, 600)


def deadman_latencies(trials: int) -> list[float]:
    sim = SimController("pulse75", MonotonicClock())
    jogger = Jogger(sim, sim.arm)
    jogger.start_watchdog()
    latencies = []
    try:
        for i in range(trials):
            request = JogRequest(JogFrame.JOINT, 0, +1 if i % 2 == 0 else -1, speed_percent=10)
            for _ in range(6):
                jogger.hold(request)
                time.sleep(CONFIRM_PERIOD_S)
            jogger.hold(request)
            last_confirm = time.monotonic()
            while sim.get_motion_status() is MotionStatus.RUNNING:
                time.sleep(0.0005)
            latencies.append(time.monotonic() - last_confirm)
    finally:
        jogger.stop_watchdog()
    return latencies


def server_latencies(trials: int) -> list[float]:
    """The pendant's own part of a press: from the jog request to the moved arm handed to viser (which then
    batches messages for up to 1/60 s before they leave), in-process on the real clock."""
    from tests.support.pages import new_page

    sim = SimController("pulse75", MonotonicClock())
    page = new_page(sim, sim.arm, mode_line="benchmark")
    moved = threading.Event()
    show = page.scene.show

    def show_and_tell(
        q: np.ndarray, gripper_opening: float, T_base_tcp: np.ndarray, now: float | None = None
    ) -> None:
        before = page.scene.last_shown
        show(q, gripper_opening, T_base_tcp, now)
        if before is not None and page.scene.last_shown is not before:
            moved.set()

    page.scene.show = show_and_tell  # type: ignore[method-assign]  # wrapped: this run sees each frame sent
    page.start()
    latencies = []
    try:
        time.sleep(1.0)
        for i in range(trials):
            moved.clear()
            pressed = time.perf_counter()
            page.jogger.hold(JogRequest(JogFrame.JOINT, 0, +1 if i % 2 == 0 else -1, speed_percent=10))
            if moved.wait(1.0):
                latencies.append(time.perf_counter() - pressed)
            time.sleep(0.1)
            page.jogger.release()
            time.sleep(0.2)
    finally:
        page.stop()
    return latencies


# Before the page loads: timestamp every server message reaching the page, and every press.
_INSTRUMENT = """
window.__messages = [];
window.__pressedAt = null;
const NativeWorker = window.Worker;  // viser's websocket lives in a worker that posts each message over
window.Worker = function (...args) {
  const worker = new NativeWorker(...args);
  // Only messages that move the arm's links count: status, dashboard and log updates arrive too.
  worker.addEventListener('message', (event) => {
    const batch = event.data && event.data.messages ? event.data.messages : [event.data];
    if (batch.some(m => m && typeof m.name === 'string' && m.name.startsWith('/arm/'))) {
      window.__messages.push(performance.now());
    }
  });
  return worker;
};
window.Worker.prototype = NativeWorker.prototype;
document.addEventListener('pointerdown', () => { window.__pressedAt = performance.now(); }, true);
"""
_FIRST_UPDATE_AFTER_PRESS = "() => window.__messages.find(t => t > window.__pressedAt) ?? null"


def browser_latencies(trials: int) -> list[float]:
    from playwright.sync_api import sync_playwright

    latencies = []
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        api = pendant.api
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": VIEWPORT[0], "height": VIEWPORT[1]})
        page.add_init_script(_INSTRUMENT)
        page.goto(pendant.ui_url)
        page.locator("#motion-state").wait_for(timeout=30_000)
        button = page.get_by_role("button", name="J1+", exact=True)
        button.wait_for(timeout=30_000)
        time.sleep(2.0)  # the docked panel opens as the page loads: press where the button comes to rest
        box = button.bounding_box()
        assert box is not None
        page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
        for _ in range(trials):
            page.mouse.down()
            page.wait_for_function(f"({_FIRST_UPDATE_AFTER_PRESS})() !== null", timeout=5_000)
            first = page.evaluate(_FIRST_UPDATE_AFTER_PRESS)
            latencies.append((first - page.evaluate("window.__pressedAt")) / 1000.0)
            time.sleep(0.2)
            page.mouse.up()
            wait_until(lambda: api.get("/status/motion").text.strip('"') == "IDLE", what="IDLE")
            time.sleep(0.3)
        browser.close()
    return latencies


# Frame intervals of the page, and how long the main thread is blocked at a time (what a release waits for).
_FRAMES = """
window.__frames = []; (function f(t) { window.__frames.push(t); requestAnimationFrame(f); })(0);
window.__blocked = [];
new PerformanceObserver((list) => { for (const e of list.getEntries()) window.__blocked.push(e.duration); })
  .observe({ type: "longtask" });
"""


def frame_report(rounds: int) -> None:
    """The page while the arm moves (a 30° PUT /pose at 10 %), at 1400x900 in software WebGL: viser's own
    rendering (?render=viser) against the pendant's (no MSAA, pixel ratio 0.75, frames spaced), one page
    at a time, alternating, so both see the same load."""
    from playwright.sync_api import sync_playwright

    variants = {"viser's rendering": "?render=viser", "the pendant's": ""}
    frames: dict[str, list[float]] = {name: [] for name in variants}
    blocked: dict[str, list[float]] = {name: [] for name in variants}
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        api = pendant.api
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        for i in range(rounds):
            for name, query in variants.items():
                page = browser.new_page(viewport={"width": 1400, "height": 900})
                page.add_init_script(_FRAMES)
                page.goto(f"{pendant.ui_url}{query}")
                page.locator("#jog-pad").wait_for(timeout=90_000)
                time.sleep(1.5)
                target = api.get("/pose").json()["angles"]
                target[0] += 30.0 if i % 2 == 0 else -30.0
                api.put("/pose", params={"speed": 10}, json={"angles": target})
                time.sleep(0.3)
                page.evaluate("window.__frames.length = 0; window.__blocked.length = 0")
                time.sleep(2.0)
                stamps = page.evaluate("window.__frames.slice()")
                frames[name] += [(b - a) / 1000.0 for a, b in itertools.pairwise(stamps)]
                blocked[name] += [d / 1000.0 for d in page.evaluate("window.__blocked.slice()")]
                api.put("/freeze")
                page.close()
        browser.close()
    for name in variants:
        if frames[name]:
            _report(f"frame interval while the arm moves, {name}", frames[name])
        if blocked[name]:
            _report(f"main thread blocked at a time (long tasks), {name}", blocked[name])


# Each release as the page saw it: when the browser stamped the input (event.timeStamp) and when the page's
# handler ran, both on the wall clock.
_LIFTS = """
window.__lifts = [];
document.addEventListener("pointerup", (e) => window.__lifts.push(
  [performance.timeOrigin + e.timeStamp, performance.timeOrigin + performance.now()]), true);
"""


def release_stages(page: Page, timeline: Timeline) -> tuple[float, float]:
    """(input stamped by the browser -> arm still, page handled the release -> arm still), in seconds."""
    stamped, handled = page.evaluate("window.__lifts.at(-1)")
    last = timeline.last_motion_s()
    return last - timeline.at(stamped / 1000.0), last - timeline.at(handled / 1000.0)


def hold_report(holds: int) -> None:
    """Hold J1 by mouse and by finger against the API-sent equivalent; a swipe; the frame time."""
    from playwright.sync_api import sync_playwright

    from tests.support.jog_measure import api_hold, close_while_held, mouse_hold, touch_hold, touch_swipe

    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        api = pendant.api
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 900}, has_touch=True)
        page.add_init_script(_FRAMES)
        page.add_init_script(_LIFTS)
        page.goto(pendant.ui_url)
        page.locator("#jog-pad").wait_for(timeout=90_000)
        time.sleep(2.0)
        cdp = page.context.new_cdp_session(page)
        stages: dict[str, list[tuple[float, float]]] = {"mouse": [], "touch": []}
        results: dict[str, list] = {"api": [], "mouse": [], "touch": []}
        frames: list[float] = []
        for i in range(holds):
            label = "J1+" if i % 2 == 0 else "J1-"
            results["api"].append(api_hold(api, 1.0, +1 if i % 2 == 0 else -1))
            page.evaluate("window.__frames.length = 0")
            results["mouse"].append(mouse_hold(page, api, label, 1.0))
            stages["mouse"].append(release_stages(page, results["mouse"][-1]))
            stamps = page.evaluate("window.__frames.slice()")
            frames += [b - a for a, b in itertools.pairwise(stamps)]
            results["touch"].append(touch_hold(page, cdp, api, label, 1.0))
            stages["touch"].append(release_stages(page, results["touch"][-1]))
        swipes = [touch_swipe(page, cdp, api, "J1+").moved_deg for _ in range(max(2, holds // 2))]
        page.close()
        closed = []
        for _ in range(max(2, holds // 2)):
            tab = browser.new_page(viewport={"width": 1400, "height": 900})
            tab.goto(pendant.ui_url)
            tab.locator("#jog-pad").wait_for(timeout=90_000)
            time.sleep(1.0)
            closed.append(close_while_held(tab, api, "J1+", 0.6).stop_after_release_s())
        browser.close()
    api_deg = statistics.median(t.moved_deg for t in results["api"])
    print(f"hold 1.0 s, API-sent equivalent: J1 moved median {api_deg:.2f} deg")
    for how in ("mouse", "touch"):
        runs = results[how]
        ratios = [t.moved_deg / api_deg * 100 for t in runs]
        firsts = [t.first_motion_s() for t in runs if t.first_motion_s() is not None]
        _report(f"{how}: press -> first motion", firsts)
        _report(f"{how}: release sent by the driver -> arm still", [t.stop_after_release_s() for t in runs])
        _report(f"{how}: release stamped by the browser -> arm still", [a for a, _ in stages[how]])
        _report(f"{how}: release handled by the page -> arm still", [b for _, b in stages[how]])
        print(
            f"{how}: hold 1.0 s moved {min(ratios):.0f}-{max(ratios):.0f} % of the API-sent motion "
            f"(median {statistics.median(ratios):.0f} %), "
            f"stalls while held: {sum(t.stalls_while_held() for t in runs)}"
        )
    print(f"swipe starting on J1+: J1 moved {max(swipes):.3f} deg at most ({len(swipes)} swipes)")
    _report("tab closed while J1+ is held -> arm still", closed)
    if frames:
        _report("frame time while the arm moves (1400x900)", [f / 1000.0 for f in frames])


# Each gesture's stages as the page saw them (wall clock): the pointer handled, the hold and the release
# handed to the worker (which sends them on viser's socket).
_STAGES = """
window.__stages = [];
(() => {
  const mark = (name) => window.__stages.push([name, performance.timeOrigin + performance.now()]);
  const post = Worker.prototype.postMessage;
  Worker.prototype.postMessage = function (message, ...rest) {
    const type = message && message.type;
    if (type === "pendant_hold" || type === "pendant_release") mark(type);
    return post.call(this, message, ...rest);
  };
  document.addEventListener("pointerdown", () => mark("down"), true);
  document.addEventListener("pointerup", () => mark("up"), true);
})();
"""
TABLET = (768, 1024)


def gesture_stages(page: Page, timeline: Timeline) -> dict[str, float]:
    """Where a press and a release spend their time (s), on the gesture's timeline (0 = press sent)."""
    marks: dict[str, float] = {}
    for name, wall in page.evaluate("window.__stages.splice(0)"):
        marks.setdefault(name, timeline.at(wall / 1000.0))  # the first of each: a hold re-sent after a stall
    first, still = timeline.first_motion_s(), timeline.last_motion_s()
    stages = {}
    if "down" in marks and "pendant_hold" in marks and first is not None:
        stages["press sent -> handled by the page"] = marks["down"]
        stages["handled -> hold sent (touch: swipe check + a frame)"] = marks["pendant_hold"] - marks["down"]
        stages["hold sent -> first motion"] = first - marks["pendant_hold"]
    if "up" in marks and "pendant_release" in marks:
        stages["release sent -> handled by the page"] = marks["up"] - timeline.released_at
        stages["handled -> release sent"] = marks["pendant_release"] - marks["up"]
        stages["release sent -> arm still"] = still - marks["pendant_release"]
    return stages


def tablet_report(holds: int) -> None:
    """Hold J1 1.0 s on the tablet layout (768x1024, touch enabled) by API, mouse and finger, alternating in
    one run (so all three see the same load): the share of the API-sent motion, press -> first motion,
    release -> arm still, and where a press and a release spend their time."""
    import os

    from playwright.sync_api import sync_playwright

    from tests.support.jog_measure import api_hold, ensure_operator, mouse_hold, touch_hold

    load_before = os.getloadavg()[0]
    runs: dict[str, list] = {"api": [], "mouse": [], "touch": []}
    stages: dict[str, dict[str, list[float]]] = {"mouse": {}, "touch": {}}
    with running_pendant_ui() as pendant, sync_playwright() as playwright:
        api = pendant.api
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": TABLET[0], "height": TABLET[1]}, has_touch=True)
        page.add_init_script(_STAGES)
        page.goto(pendant.ui_url)
        ensure_operator(page)
        cdp = page.context.new_cdp_session(page)
        for i in range(holds):
            label, direction = ("J1+", +1) if i % 2 == 0 else ("J1-", -1)
            runs["api"].append(api_hold(api, 1.0, direction))
            for how in ("mouse", "touch"):
                page.evaluate("window.__stages.length = 0")
                if how == "mouse":
                    runs[how].append(mouse_hold(page, api, label, 1.0))
                else:
                    runs[how].append(touch_hold(page, cdp, api, label, 1.0))
                for name, value in gesture_stages(page, runs[how][-1]).items():
                    stages[how].setdefault(name, []).append(value)
        browser.close()
    load = f"load average {load_before:.1f}-{os.getloadavg()[0]:.1f}"
    api_deg = statistics.median(t.moved_deg for t in runs["api"])
    print(f"tablet 768x1024, hold J1 1.0 s x {holds}, {load}")
    print(f"tablet API-sent: moved median {api_deg:.2f} deg")
    _report("tablet API: freeze sent -> arm still", [t.stop_after_release_s() for t in runs["api"]])
    for how in ("mouse", "touch"):
        ratios = [t.moved_deg / api_deg * 100 for t in runs[how]]
        print(
            f"tablet {how}: hold 1.0 s moved median {statistics.median(ratios):.0f} % "
            f"({min(ratios):.0f}-{max(ratios):.0f} %) of the API-sent motion, "
            f"stalls while held: {sum(t.stalls_while_held() for t in runs[how])}"
        )
        _report(f"tablet {how}: press -> first motion", [t.first_motion_s() or 0.0 for t in runs[how]])
        _report(f"tablet {how}: release sent -> arm still", [t.stop_after_release_s() for t in runs[how]])
        for name, values in stages[how].items():
            _report(f"tablet {how}:   {name}", values)


def _report(name: str, values: list[float]) -> None:
    ms = sorted(v * 1000 for v in values)
    p99 = ms[min(len(ms) - 1, round(0.99 * (len(ms) - 1)))]
    print(f"{name}: n={len(ms)} p50 {statistics.median(ms):.1f} ms, p99 {p99:.1f} ms, max {ms[-1]:.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=20)
    parser.add_argument("--holds", type=int, default=5)
    parser.add_argument("--only-browser", action="store_true", help="only part 3")
    parser.add_argument("--only-tablet", action="store_true", help="only the tablet holds (768x1024)")
    args = parser.parse_args()
    tablet_report(args.holds)
    if args.only_tablet:
        return
    frame_report(max(1, args.holds // 2))
    hold_report(args.holds)
    if args.only_browser:
        return
    _report("deadman: last confirmation -> arm frozen", deadman_latencies(args.trials))
    _report("server: jog request -> moved arm handed to viser", server_latencies(args.trials))
    _report("browser: J1+ pressed -> first pose change on the page", browser_latencies(args.trials))


if __name__ == "__main__":
    main()
