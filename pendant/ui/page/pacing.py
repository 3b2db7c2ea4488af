"""When the refresh loop reads what: the state at 30 Hz, IO and the tool at 5 Hz, the cell at 3 Hz, and the
motors at 10 Hz into the shared history (the dashboard and the recordings).

The motors go by a deadline, not by counting ticks: a stalled tick (a slow controller reply) is dropped from
the 30 Hz ticks, and a sample taken every third tick then lost its place too (a recording said to run at 10
samples/s measured 8.8). By a deadline the sample comes on the next tick instead, and the rate holds.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

REFRESH_HZ = 30.0
TICK_S = 1.0 / REFRESH_HZ
IO_EVERY_N_TICKS = 6  # IO and tool change rarely: read them at 5 Hz
CELL_EVERY_N_TICKS = 10  # the cell, system state and failures at 3 Hz (a script may change the cell)
MOTORS_PERIOD_S = 0.1  # motors at 10 Hz into the shared history
TABLE_EVERY_N_SAMPLES = 2  # the motor table and the event log redrawn at 5 Hz
PLOTS_EVERY_N_SAMPLES = 5  # the plots at 2 Hz (at most MAX_POINTS a series)


@dataclass
class Deadline:
    """Due every `period` seconds on average, on the tick nearest each deadline (`early`: half a tick).

    After a stall it catches up at most one period: one sample right after the late one, never a burst.
    """

    period: float
    next_at: float
    early: float = TICK_S / 2

    def due(self, now: float) -> bool:
        if now + self.early < self.next_at:
            return False
        self.next_at = max(self.next_at + self.period, now)
        return True


@dataclass(frozen=True)
class TickWork:
    """What one tick reads besides the state."""

    io: bool
    cell: bool
    sample: bool  # the motors, into the shared history
    table: bool  # with a sample: redraw the motor table and the event log
    plots: bool  # with a sample: redraw the plots


class RefreshSchedule:
    """The ticks at REFRESH_HZ (after a stall they go on from then, they do not race to catch up) and what
    each one reads."""

    def __init__(self, now: float) -> None:
        self.tick = 0
        self.next_tick_at = now
        # First due on tick 1, then every third tick while nothing stalls: never on the IO read's tick.
        self.motors = Deadline(MOTORS_PERIOD_S, now + TICK_S)
        self.samples = 0

    def work(self, now: float) -> TickWork:
        io = self.tick % IO_EVERY_N_TICKS == 0
        sample = not io and self.motors.due(now)  # a sample due on the IO tick waits for the next one
        table = sample and self.samples % TABLE_EVERY_N_SAMPLES == 0
        plots = sample and self.samples % PLOTS_EVERY_N_SAMPLES == 0
        self.samples += sample
        return TickWork(
            io=io, cell=self.tick % CELL_EVERY_N_TICKS == 2, sample=sample, table=table, plots=plots
        )

    def wait_s(self, now: float) -> float:
        """End the tick: how long to wait for the next one."""
        self.tick += 1
        self.next_tick_at += TICK_S
        return max(0.0, self.next_tick_at - now)

    def resume(self, now: float, *, woken: bool) -> None:
        """The wait ended (`woken`: early, a jog started)."""
        if woken:
            self.next_tick_at = now  # the ticks go on from now
        self.next_tick_at = max(self.next_tick_at, now - TICK_S)  # after a stall, do not race to catch up


def run_ticks(
    tick: Callable[[TickWork, bool], None],
    *,
    stopped: Callable[[], bool],
    wait: Callable[[float], bool],
    clock: Callable[[], float] = time.monotonic,
) -> None:
    """Call `tick(work, woken)` on schedule until `stopped()`; `wait(timeout)` returns True when woken early
    (the tick after a wake-up flushes its reading at once)."""
    schedule = RefreshSchedule(clock())
    woken = False
    while not stopped():
        tick(schedule.work(clock()), woken)
        woken = wait(schedule.wait_s(clock()))
        schedule.resume(clock(), woken=woken)


class RefreshLoop:
    """The refresh thread: `tick(work, woken)` on schedule until `stop`; `wake` (a jog started) shows its
    first motion now, not at the next tick."""

    def __init__(self, tick: Callable[[TickWork, bool], None]) -> None:
        self._tick = tick
        self._stopped = threading.Event()
        self._woken = threading.Event()
        self._thread = threading.Thread(target=self._run, name="pendant-refresh", daemon=True)

    def start(self) -> None:
        self._thread.start()

    def wake(self) -> None:
        self._woken.set()

    def stop(self, timeout_s: float = 2.0) -> None:
        self._stopped.set()
        self._woken.set()
        if self._thread.is_alive():
            self._thread.join(timeout=timeout_s)

    def _run(self) -> None:
        run_ticks(self._tick, stopped=self._stopped.is_set, wait=self._woken_within)

    def _woken_within(self, timeout_s: float) -> bool:
        woken = self._woken.wait(timeout_s)
        if woken:
            self._woken.clear()
        return woken
