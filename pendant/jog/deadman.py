"""The server-side deadman: jogging stops when the operator's browser stops confirming."""

from __future__ import annotations

import threading
from collections.abc import Callable

DEADMAN_TIMEOUT_S = 0.2


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
