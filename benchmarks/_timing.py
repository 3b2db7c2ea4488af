"""The timing loop the benchmarks share: an action timed again and again on the wall clock."""

from __future__ import annotations

import time
from collections.abc import Callable


def wall_times_s(action: Callable[[], object], repeats: int) -> list[float]:
    """The wall time of each of `repeats` calls of `action`, in seconds (time.perf_counter)."""
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        action()
        times.append(time.perf_counter() - started)
    return times
