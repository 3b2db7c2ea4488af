"""Clocks the simulator reads its time from: the real monotonic clock, a scaled one (faster or slower than
the wall clock, `--time-scale`), or a fake one tests advance by hand."""

from __future__ import annotations

import contextlib
import heapq
import math
import threading
import time
from collections.abc import Callable, Iterator
from typing import Protocol, runtime_checkable


@runtime_checkable
class Clock(Protocol):
    """A source of time in seconds; only differences matter."""

    def now(self) -> float: ...

    def unix_time(self, t: float) -> float:
        """The Unix time of clock reading t (for timestamps the API reports)."""
        ...


@runtime_checkable
class HoldableClock(Protocol):
    """A clock whose simulated time can be stopped and let go again (ScaledClock)."""

    def hold(self) -> float: ...

    def remove_stop(self, t: float) -> None: ...


class MonotonicClock:
    """`time.monotonic`: the clock of a running pendant."""

    def __init__(self) -> None:
        self._unix_offset = time.time() - time.monotonic()

    def now(self) -> float:
        return time.monotonic()

    def unix_time(self, t: float) -> float:
        return self._unix_offset + t


class FakeClock:
    """A clock that only moves when told to: tests and benchmarks advance it instead of sleeping."""

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)
        self._unix0 = time.time() - self._now

    def unix_time(self, t: float) -> float:
        return self._unix0 + t

    def now(self) -> float:
        return self._now

    def advance(self, dt: float) -> float:
        """Move time forward by `dt` seconds (>= 0); returns the new time."""
        if dt < 0:
            raise ValueError(f"a clock cannot go backwards (dt={dt})")
        self._now += float(dt)
        return self._now


# The time scales the simulator is exact at: below 0.1 nobody waits that long on purpose, and above 1000 a
# millisecond of the wall clock is a simulated second (the API's own latency would show in every motion).
MIN_TIME_SCALE = 0.1
MAX_TIME_SCALE = 1000.0


def check_time_scale(scale: float) -> float:
    """`scale` as a float, or ValueError naming the range."""
    scale = float(scale)
    if not (math.isfinite(scale) and MIN_TIME_SCALE <= scale <= MAX_TIME_SCALE):
        raise ValueError(
            f"time scale must be between {MIN_TIME_SCALE:g} and {MAX_TIME_SCALE:g} (got {scale:g})"
        )
    return scale


class ScaledClock:
    """Simulated time running `scale` times the wall clock (`time.monotonic`), from 0 at creation.

    Everything the simulator times (motions, gripper waits, the servos' heating, what it reports) reads this
    clock, so a time scale changes all of it at once and the simulator stays consistent.

    Stops: `add_stop(t)` keeps simulated time from passing t until `remove_stop(t)`; readers meanwhile see t.
    Scripted events use them to happen at exactly their simulated time, however late their thread wakes up.
    When the last stop before "now" goes, time resumes from the stop (it does not jump the time it was held).
    """

    def __init__(self, scale: float = 1.0, wall: Callable[[], float] = time.monotonic) -> None:
        self._scale = check_time_scale(scale)
        self._wall = wall  # the wall clock (tests pass a fake one)
        self._lock = threading.Lock()
        self._sim0 = 0.0  # simulated time at wall time _wall0
        self._wall0 = wall()
        self._stops: list[float] = []  # a heap: the earliest stop first
        self._unix0 = time.time()  # Unix time at simulated time 0

    @property
    def scale(self) -> float:
        return self._scale

    def now(self) -> float:
        with self._lock:
            return self._now_locked()

    def _now_locked(self) -> float:
        t = self._sim0 + self._scale * (self._wall() - self._wall0)
        return min(t, self._stops[0]) if self._stops else t

    def _rebase(self, sim_now: float) -> None:
        self._sim0, self._wall0 = sim_now, self._wall()

    def set_scale(self, scale: float) -> None:
        """Run at `scale` from now on; the time read so far is kept."""
        scale = check_time_scale(scale)
        with self._lock:
            self._rebase(self._now_locked())
            self._scale = scale

    def add_stop(self, t: float) -> None:
        """Keep simulated time from passing t; ValueError if it already has (time never runs backwards)."""
        with self._lock:
            now = self._now_locked()
            if t < now:
                raise ValueError(f"simulated time {t:g} s has passed (it is {now:g} s)")
            heapq.heappush(self._stops, float(t))

    def hold(self) -> float:
        """Stop simulated time where it is now (a stop at the current reading); returns that time."""
        with self._lock:
            t = self._now_locked()
            heapq.heappush(self._stops, t)
            return t

    def remove_stop(self, t: float) -> None:
        """Let time pass t again (a stop already cleared is no error)."""
        with self._lock:
            held = self._now_locked()
            if float(t) in self._stops:
                self._stops.remove(float(t))
                heapq.heapify(self._stops)
            self._rebase(held)

    def clear_stops(self) -> None:
        with self._lock:
            held = self._now_locked()
            self._stops.clear()
            self._rebase(held)

    def wall_seconds_until(self, t: float) -> float:
        """How long the wall clock takes to reach simulated time t (0 if it has, or a stop holds it there)."""
        with self._lock:
            free = self._sim0 + self._scale * (self._wall() - self._wall0)
            return max(0.0, (t - free) / self._scale)

    def unix_time(self, t: float) -> float:
        """The Unix time a timestamp taken at simulated time t carries: the start's wall time plus t."""
        return self._unix0 + t


@contextlib.contextmanager
def paused(clock: Clock) -> Iterator[None]:
    """Simulated time stands still inside, on a clock that can be held (ScaledClock): the simulator's own
    computing (planning a motion) then takes no simulated time, so a run K times faster stays exact. The
    real-time clocks run on, as a real controller's would while it plans."""
    if not isinstance(clock, HoldableClock):
        yield
        return
    held = clock.hold()
    try:
        yield
    finally:
        clock.remove_stop(held)
