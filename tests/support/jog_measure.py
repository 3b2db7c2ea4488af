"""Measuring a jog the way the operator feels it: the arm's pose sampled over the API while a real browser
holds a jog button with the mouse or a finger, against the same motion sent straight to the API.

Used by tests/browser/test_jog_hold.py (behaviour, generous bounds) and benchmarks/jog.py (the numbers).
"""

from __future__ import annotations

import itertools
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import httpx

from tests.support.waiting import wait_idle, wait_until

JOG_SPEED_PERCENT = 10
FAR_DEG = 90.0  # a target further than any hold reaches: the API-sent motion is frozen on the way
MOVED_DEG = 0.01  # J1 changed by more than this: the arm moved
STILL_S = 0.15  # no change for this long after the last one: the arm is still


@dataclass(frozen=True)
class Timeline:
    """J1 (degrees) sampled over the API while something moves it; times relative to the press."""

    samples: list[tuple[float, float]]
    released_at: float
    origin_wall: float = 0.0  # the wall clock (time.time()) at t = 0: to place the page's own timestamps

    def at(self, wall: float) -> float:
        """A wall-clock instant (a page's `performance.timeOrigin + performance.now()`) on this timeline."""
        return wall - self.origin_wall

    @property
    def moved_deg(self) -> float:
        return abs(self.samples[-1][1] - self.samples[0][1])

    def first_motion_s(self) -> float | None:
        start = self.samples[0][1]
        return next((t for t, v in self.samples if abs(v - start) > MOVED_DEG), None)

    def last_motion_s(self) -> float:
        """When J1 last changed: the arm is still from then on."""
        last = self.samples[0][0]
        for (_, a), (t, b) in zip(self.samples, self.samples[1:], strict=False):
            if b != a:
                last = t
        return last

    def stop_after_release_s(self) -> float:
        return max(0.0, self.last_motion_s() - self.released_at)

    def stalls_while_held(self, gap_s: float = STILL_S) -> int:
        """How often J1 stood still for `gap_s` between the first motion and the release (a deadman stop
        inside one press shows up as one)."""
        first = self.first_motion_s()
        if first is None:
            return 0
        stalls, since = 0, first
        for (_, a), (t, b) in zip(self.samples, self.samples[1:], strict=False):
            if t <= first or t > self.released_at:
                continue
            if b != a:
                if t - since > gap_s:
                    stalls += 1
                since = t
        return stalls


SAMPLE_GAP_S = 0.004  # ~200 readings a second: fine enough for stops, and leaves the page its CPU
MOVING_POLL_S = 0.02  # how often wait_moving looks at the samples (they come from the sampler's thread)


class PoseSampler:
    """Reads J1 over the API about every SAMPLE_GAP_S, on a thread, between `start()` and `stop()`. (As fast
    as loopback allowed, it took a core from the browser on a 2-core machine: the measured page stalled.)"""

    def __init__(self, api: httpx.Client) -> None:
        self._api = api
        self._samples: list[tuple[float, float]] = []
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self.t0 = 0.0
        self.t0_wall = 0.0

    def _run(self) -> None:
        while not self._stop.is_set():
            j1 = self._api.get("/pose").json()["angles"][0]
            self._samples.append((time.monotonic() - self.t0, j1))
            self._stop.wait(SAMPLE_GAP_S)

    def start(self) -> None:
        self.t0 = time.monotonic()
        self.t0_wall = time.time()
        self._thread.start()
        while not self._samples:
            time.sleep(0.001)

    def mark(self) -> float:
        return time.monotonic() - self.t0

    def wait_moving(self, timeout_s: float) -> bool:
        """Wait until J1 has read two different values (a press reached the arm), at most `timeout_s`."""
        try:
            wait_until(
                lambda: len({j1 for _, j1 in list(self._samples)}) > 1, timeout_s, "J1 moving", MOVING_POLL_S
            )
        except TimeoutError:
            return False
        return True

    def stop(self, released_at: float, settle_s: float = 0.6) -> Timeline:
        time.sleep(settle_s)
        self._stop.set()
        self._thread.join()
        return Timeline(list(self._samples), released_at, self.t0_wall)


def api_hold(api: httpx.Client, hold_s: float, direction: int = +1, far_deg: float = FAR_DEG) -> Timeline:
    """The API-sent equivalent of holding J1 for `hold_s`: PUT /pose at the jog speed, PUT /freeze later
    (`far_deg`: further than the hold reaches, ~11 deg a second)."""
    wait_idle(api)
    target = api.get("/pose").json()["angles"]
    target[0] += direction * far_deg
    return timed_press(
        api,
        lambda: api.put(
            "/pose", params={"speed": JOG_SPEED_PERCENT}, json={"angles": target}
        ).raise_for_status(),
        lambda: api.put("/freeze").raise_for_status(),
        hold_s,
    )


def timed_press(
    api: httpx.Client, press: Callable[[], object], release: Callable[[], object], hold_s: float
) -> Timeline:
    """J1 sampled from just before `press()` until a while after `release()`, which comes `hold_s` after the
    press began (at once if the press itself took longer); times relative to the press."""
    sampler = PoseSampler(api)
    sampler.start()
    pressed = sampler.mark()
    press()
    time.sleep(max(0.0, hold_s - (sampler.mark() - pressed)))
    released = sampler.mark()
    release()
    return _relative(sampler.stop(released), pressed)


def button_box(page: Any, label: str) -> dict[str, float]:
    """Where `label` is (the pad is redrawn as the values change: a button may be replaced under a read)."""
    for _ in range(10):
        box = page.get_by_role("button", name=label, exact=True).bounding_box()
        if box is not None:
            return box
        time.sleep(0.1)
    raise AssertionError(f"{label} is not on the page")


def button_centre(page: Any, label: str) -> tuple[float, float]:
    box = button_box(page, label)
    return box["x"] + box["width"] / 2, box["y"] + box["height"] / 2


def open_as_operator(page: Any, url: str) -> None:
    """Load the pendant and make sure this page has control (a page that left a moment ago may still have
    held it when this one joined)."""
    page.goto(url)
    ensure_operator(page)


def ensure_operator(page: Any) -> None:
    page.locator("#jog-pad").wait_for(timeout=90_000)
    enabled = page.locator("#jog-pad button:not([disabled])").first
    take = page.get_by_role("button", name="Take control")
    deadline = time.monotonic() + 60.0
    while not enabled.is_visible():
        assert time.monotonic() < deadline, "this page never got control"
        if take.is_visible():  # a viewer (another page had control when this one joined): take it
            take.click()
        time.sleep(0.5)
    # A page still building its scene (meshes, shaders) stalls its main thread for seconds, and a stall past
    # the page's 400 ms lets the deadman cut a hold (as it must): start when its frames come steadily.
    wait_settled(page)


# The main thread's gaps, by a 50 ms timer (not by animation frames: the page spaces those itself, one a
# second with ?frame_ms=1000, and a frame gap then said nothing of the page and made every wait run out,
# 20 s), and at least one frame drawn within the quiet stretch (the view draws at all).
SETTLED = """([quietMs, maxGapMs, timeoutMs]) => new Promise((done) => {
  const start = performance.now();
  let last = start, quietSince = start, framedAt = -Infinity, ended = false;
  const frame = () => { framedAt = performance.now(); if (!ended) requestAnimationFrame(frame); };
  requestAnimationFrame(frame);
  const tick = () => {
    const now = performance.now();
    if (now - last > maxGapMs) quietSince = now;
    last = now;
    const quiet = now - quietSince >= quietMs && framedAt >= quietSince;
    if (quiet || now - start > timeoutMs) { ended = true; done(quiet); return; }
    setTimeout(tick, 50);
  };
  setTimeout(tick, 50);
})"""


def wait_settled(page: Any, quiet_ms: int = 1_500, max_gap_ms: int = 250, timeout_ms: int = 20_000) -> bool:
    """Wait until the page's main thread has been free for `quiet_ms` (no gap over `max_gap_ms`) and drew a
    frame meanwhile (at most `timeout_ms`; False if it never settled: a machine that busy is the test's to
    report, not this wait's)."""
    return bool(page.evaluate(SETTLED, [quiet_ms, max_gap_ms, timeout_ms]))


HANG_MAIN_THREAD = """(ms) => setTimeout(() => {
    window.__hungAt = performance.timeOrigin + performance.now();
    while (performance.timeOrigin + performance.now() - window.__hungAt < ms) {}
}, 0)"""


def hang_main_thread(page: Any, sampler: PoseSampler, seconds: float) -> float:
    """Hang the page's main thread for `seconds` (a busy loop, as a stuck script does) and return when it
    began on the sampler's clock; returns once the page runs again."""
    page.evaluate(HANG_MAIN_THREAD, seconds * 1000)
    hung_wall_ms = page.evaluate("window.__hungAt")  # answered once the page runs again
    # The page's clock is the wall clock; the sampler's is monotonic, from its start.
    return float(hung_wall_ms) / 1000 - (time.time() - time.monotonic()) - sampler.t0


def pose_changes(timeline: Timeline) -> list[float]:
    """The times at which J1 read differently from the sample before."""
    return [t for (t, a), (_, b) in itertools.pairwise(timeline.samples) if a != b]


def mouse_hold(page: Any, api: httpx.Client, label: str, hold_s: float) -> Timeline:
    wait_idle(api)
    page.mouse.move(*button_centre(page, label))
    return timed_press(api, page.mouse.down, page.mouse.up, hold_s)


def key_hold(page: Any, api: httpx.Client, label: str, hold_s: float, key: str = "Space") -> Timeline:
    """Space (or Enter) held down on the focused `label` for `hold_s`, as a keyboard user jogs."""
    wait_idle(api)
    page.get_by_role("button", name=label, exact=True).focus()
    return timed_press(api, lambda: page.keyboard.down(key), lambda: page.keyboard.up(key), hold_s)


def close_while_held(page: Any, api: httpx.Client, label: str, hold_s: float) -> Timeline:
    """Hold `label` by mouse, then close the tab while it is still held, as a person closes it (the page's
    unload handlers run; then the worker and the socket die)."""
    wait_idle(api)
    page.mouse.move(*button_centre(page, label))
    return timed_press(api, page.mouse.down, lambda: page.close(run_before_unload=True), hold_s)


def settled(page: Any, label: str, timeout_s: float = 15.0, still_s: float = 0.3) -> None:
    """Wait until `label` stays put for `still_s`: while the page loads, the docked panel opens and its text
    wraps narrower for a moment (on a loaded machine, J1 was seen 400 px lower for a second). A page that
    draws a frame a second (`?frame_ms=1000`) moves it a step a second: wait longer than that there."""
    deadline = time.monotonic() + timeout_s
    last = button_box(page, label)
    while time.monotonic() < deadline:
        time.sleep(still_s)
        now = button_box(page, label)
        if abs(now["x"] - last["x"]) < 0.5 and abs(now["y"] - last["y"]) < 0.5:
            return
        last = now


def on_top(page: Any, name: str) -> bool:
    """The button is inside the viewport and nothing covers its centre."""
    return bool(
        page.get_by_role("button", name=name, exact=True).evaluate(
            """(b) => {
                const r = b.getBoundingClientRect(), x = r.left + r.width / 2, y = r.top + r.height / 2;
                if (x < 0 || y < 0 || x > innerWidth || y > innerHeight) return false;
                const hit = document.elementFromPoint(x, y);
                return hit !== null && b.contains(hit);
            }"""
        )
    )


def touch(cdp: Any, kind: str, x: float, y: float) -> None:
    points = [] if kind == "touchEnd" else [{"x": x, "y": y, "id": 1}]
    cdp.send("Input.dispatchTouchEvent", {"type": kind, "touchPoints": points})


def touch_hold(page: Any, cdp: Any, api: httpx.Client, label: str, hold_s: float) -> Timeline:
    """A finger on `label` for `hold_s`, then lifted (the page must have been opened with has_touch)."""
    wait_idle(api)
    x, y = button_centre(page, label)
    return timed_press(
        api, lambda: touch(cdp, "touchStart", x, y), lambda: touch(cdp, "touchEnd", x, y), hold_s
    )


def touch_swipe(page: Any, cdp: Any, api: httpx.Client, label: str, distance_px: float = 150.0) -> Timeline:
    """A finger put on `label` and swiped upwards (to scroll the panel) over 0.2 s, then lifted.

    Chromium plays the whole gesture itself (Input.synthesizeScrollGesture): its first move follows the touch
    within a frame, as a real finger's does, however late this process gets to send anything. Sent as one
    CDP touch event at a time, each waits for the page to handle the one before: on a loaded machine the
    first move then came after the page had rightly decided that a finger held still for 60 ms holds."""
    wait_idle(api)
    x, y = button_centre(page, label)
    swipe = {
        "x": x,
        "y": y,
        "yDistance": -distance_px,  # the finger goes up (the content scrolls down)
        "speed": round(distance_px / SWIPE_S),
        "gestureSourceType": "touch",
        "preventFling": True,
    }
    return timed_press(api, lambda: cdp.send("Input.synthesizeScrollGesture", swipe), lambda: None, 0.0)


SWIPE_S = 0.2


def _relative(timeline: Timeline, pressed: float) -> Timeline:
    samples = [(t - pressed, v) for t, v in timeline.samples]
    return Timeline(samples, timeline.released_at - pressed, timeline.origin_wall + pressed)
