"""The refresh loop's pacing on a fake clock: the motors are sampled at 10 Hz on average even when ticks stall
(a slow controller reply), catching up at most one sample after a stall; the other reads keep their rates."""

from __future__ import annotations

import itertools
from collections.abc import Callable

from pendant.sim import FakeClock, SimController
from pendant.telemetry.history import HISTORY_S
from pendant.ui.page.pacing import REFRESH_HZ, TickWork, run_ticks
from tests.support.pages import pendant_page

SAMPLE_HZ = 10.0
TICK_S = 1.0 / REFRESH_HZ
RATE_TOL = 0.01  # relative: one sample in 100


class FakeTime:
    """The loop's clock and its wait: a wait only moves the clock; nothing ever wakes the loop early."""

    def __init__(self, until_s: float) -> None:
        self.now = 0.0
        self.until_s = until_s

    def wait(self, timeout_s: float) -> bool:
        self.now += timeout_s
        return False

    def stopped(self) -> bool:
        return self.now >= self.until_s


def run(
    seconds: float,
    tick_takes_s: Callable[[int], float],
    on_tick: Callable[[float, TickWork, bool], None] | None = None,
) -> list[tuple[float, TickWork]]:
    """Every tick's start time and work over `seconds` of fake time; tick n takes `tick_takes_s(n)`."""
    fake = FakeTime(seconds)
    ticks: list[tuple[float, TickWork]] = []

    def tick(work: TickWork, woken: bool) -> None:
        ticks.append((fake.now, work))
        if on_tick is not None:
            on_tick(fake.now, work, woken)
        fake.now += tick_takes_s(len(ticks) - 1)

    run_ticks(tick, stopped=fake.stopped, wait=fake.wait, clock=lambda: fake.now)
    return ticks


def stalling(n: int) -> float:
    """Every third tick waits 80 ms on the controller (the loop drops ticks rather than racing after them);
    shorter than the sampling period, so no sample need be lost."""
    return 0.08 if n % 3 == 0 else 0.005


def sample_times(ticks: list[tuple[float, TickWork]]) -> list[float]:
    return [t for t, work in ticks if work.sample]


def test_without_stalls_every_read_keeps_its_rate_and_the_motors_never_share_the_io_tick() -> None:
    seconds = 30.0
    ticks = run(seconds, lambda n: 0.005)
    works = [work for _, work in ticks]

    def rate(kind: str) -> float:
        return sum(getattr(work, kind) for work in works) / seconds

    assert abs(len(ticks) / seconds - REFRESH_HZ) <= REFRESH_HZ * RATE_TOL
    expected = {"sample": 10.0, "table": 5.0, "plots": 2.0, "io": 5.0, "cell": 3.0}
    assert {kind: round(rate(kind), 1) for kind in expected} == expected
    assert not any(work.sample and work.io for work in works)
    gaps = [b - a for a, b in itertools.pairwise(sample_times(ticks))]
    assert min(gaps) > 0.1 - TICK_S / 2 and max(gaps) < 0.1 + TICK_S / 2  # evenly spaced, a tick apart


def test_stalled_ticks_cost_ticks_but_no_motor_samples() -> None:
    seconds = 60.0
    ticks = run(seconds, stalling)
    tick_rate = len(ticks) / seconds
    sample_rate = len(sample_times(ticks)) / seconds

    assert tick_rate < 0.9 * REFRESH_HZ  # a sample every third tick would have been under 9 a second (8.8)
    assert abs(sample_rate - SAMPLE_HZ) <= SAMPLE_HZ * RATE_TOL


def test_after_a_long_stall_one_sample_catches_up_and_no_burst_follows() -> None:
    stall_tick = 90  # three seconds in
    ticks = run(6.0, lambda n: 1.0 if n == stall_tick else 0.005)
    resumed_at = ticks[stall_tick + 1][0]
    soon_after = [t for t in sample_times(ticks) if resumed_at <= t < resumed_at + 0.1]

    assert len(soon_after) == 2  # the one due, and one catching up: not the ten missed during the stall
    later = [t for t in sample_times(ticks) if t >= resumed_at]
    gaps = [b - a for a, b in itertools.pairwise(later[1:])]
    assert min(gaps) > 0.1 - TICK_S  # then the 10 Hz pace again


def test_the_pendants_own_ticks_keep_the_shared_history_at_ten_samples_a_second(
    sim: SimController, clock: FakeClock
) -> None:
    """PendantUI's own tick on the fake clock, its ticks stalling: the shared history (what the plots and the
    recordings are made of) gets 10 samples a second."""
    seconds = 10.0
    started = clock.now()

    def pendant_tick(now: float, work: TickWork, woken: bool) -> None:
        clock.advance(started + now - clock.now())  # the telemetry stamps its samples with this clock
        page.tick(work, woken)

    with pendant_page(sim, sim.arm, clock=clock.now) as page:
        before = len(page.telemetry.window(HISTORY_S))
        run(seconds, stalling, on_tick=pendant_tick)
        samples = len(page.telemetry.window(HISTORY_S)) - before

    assert abs(samples / seconds - SAMPLE_HZ) <= SAMPLE_HZ * 0.02
