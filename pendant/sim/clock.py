"""Clocks the simulator reads its time from: the real monotonic clock, or a fake one tests advance by hand."""

from __future__ import annotations

import time
from typing import Protocol, runtime_checkable


@runtime_checkable
class Clock(Protocol):
    """A source of time in seconds; only differences matter."""

    def now(self) -> float: ...


class MonotonicClock:
    """`time.monotonic`: the clock of a running pendant."""

    def now(self) -> float:
        return time.monotonic()


class FakeClock:
    """A clock that only moves when told to: tests and benchmarks advance it instead of sleeping."""

    def __init__(self, start: float = 0.0) -> None:
        self._now = float(start)

    def now(self) -> float:
        return self._now

    def advance(self, dt: float) -> float:
        """Move time forward by `dt` seconds (>= 0); returns the new time."""
        if dt < 0:
            raise ValueError(f"a clock cannot go backwards (dt={dt})")
        self._now += float(dt)
        return self._now
