"""The server-side deadman: jogging stops when the operator's browser stops confirming."""

from __future__ import annotations

import threading
from collections.abc import Callable

DEADMAN_TIMEOUT_S = 0.2
# The watchdog woke this much later than it asked: the whole process stood still (a full garbage collection
# holds every thread: 114-139 ms with 100 browsers' panels, 2-core machine), the hold line's thread too,
# with the operator's confirmations waiting unread in its socket. Before it judges, the watchdog gives the
# line STALL_GRACE_S to read them, once: the next judgement is never put off (a process that stalls on
# every wake still gets its cut, at most STALL_GRACE_S later, plus any stall that begins within it).
WATCHDOG_STALL_S = 0.05
STALL_GRACE_S = 0.025


class Deadman:
    """Armed by `confirm()`; `expired(now)` is True once `timeout_s` passed without a confirmation."""

    def __init__(self, clock: Callable[[], float], timeout_s: float = DEADMAN_TIMEOUT_S) -> None:
        self._clock = clock
        self.timeout_s = timeout_s
        self._last_confirm: float | None = None
        self._lock = threading.Lock()

    def confirm(self) -> None:
        with self._lock:
            self._last_confirm = self._clock()

    def disarm(self) -> None:
        with self._lock:
            self._last_confirm = None

    @property
    def armed(self) -> bool:
        return self._last_confirm is not None

    def expired(self) -> bool:
        with self._lock:
            return self._last_confirm is not None and self._clock() - self._last_confirm > self.timeout_s

    def seconds_left(self) -> float | None:
        with self._lock:
            if self._last_confirm is None:
                return None
            return self.timeout_s - (self._clock() - self._last_confirm)


class StallGrace:
    """The watchdog's wakes (every `period_s`): `woke_late(now)` says when it should first give the hold
    line STALL_GRACE_S, because it woke more than WATCHDOG_STALL_S late, and never twice in a row."""

    def __init__(self, period_s: float, now: float) -> None:
        self._period_s = period_s
        self._woke = now
        self._graced = False

    def woke_late(self, now: float) -> bool:
        was, self._woke = self._woke, now
        if now - was > self._period_s + WATCHDOG_STALL_S and not self._graced:
            self._graced = True
            return True
        self._graced = False
        return False

    def restart(self, now: float) -> None:
        """The grace is over: the next wake's lateness counts from `now`."""
        self._woke = now
