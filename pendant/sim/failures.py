"""The failures the simulator really had, newest last, as GET /status/failure lists them."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from datetime import UTC, datetime

from pendant.controller.system_types import Failure, FailureLevel, FailureType

MAX_FAILURES = 50  # "recent": older ones are dropped


class FailureLog:
    """Dated by `clock_time()` (seconds since the epoch, in the simulator's own time)."""

    def __init__(self, clock_time: Callable[[], float]) -> None:
        self._clock_time = clock_time
        self._failures: deque[Failure] = deque(maxlen=MAX_FAILURES)

    def record(self, type_: FailureType, level: FailureLevel, message: str) -> None:
        date = datetime.fromtimestamp(self._clock_time(), UTC).isoformat(timespec="milliseconds")
        self._failures.append(Failure(type=type_, message=message, date=date, level=level))

    def recent(self) -> list[Failure]:
        return list(self._failures)

    def clear(self) -> None:
        self._failures.clear()
