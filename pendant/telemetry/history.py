"""The motors' angles, currents and temperatures in shared ring buffers: the last 60 s at the sampling rate,
and the last hour at 2 Hz (the dashboard's longer windows)."""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from pendant.controller.types import MotorStatus

HISTORY_S = 60.0
LONG_HISTORY_S = 3600.0
LONG_PERIOD_S = 0.5  # the hour's resolution: 7,200 samples, already more than a plot shows
MAX_SAMPLE_HZ = 20.0  # sizes the ring: faster sampling would keep less than HISTORY_S
N_MOTORS = 6


@dataclass(frozen=True)
class HistoryWindow:
    """Samples oldest first; `t` in seconds relative to the newest sample (<= 0)."""

    t: np.ndarray  # (n,)
    angle_deg: np.ndarray  # (n, 6)
    current_a: np.ndarray  # (n, 6) RMS
    stator_c: np.ndarray  # (n, 6)

    def __len__(self) -> int:
        return len(self.t)


class MotorHistory:
    """A fixed-size ring of (time, angle, RMS current, stator temperature) per motor; thread-safe."""

    def __init__(
        self, seconds: float = HISTORY_S, max_rate_hz: float = MAX_SAMPLE_HZ, min_period_s: float = 0.0
    ) -> None:
        """`min_period_s`: a sample closer than this to the previous one kept is skipped (a coarser ring)."""
        self.seconds = seconds
        self._min_period_s = min_period_s
        self._last_t = -np.inf
        self._capacity = int(seconds * max_rate_hz) + 1
        self._t = np.zeros(self._capacity)
        self._values = np.zeros((self._capacity, 3, N_MOTORS))
        self._next = 0
        self._count = 0
        self._lock = threading.Lock()

    def append(self, t: float, motors: list[MotorStatus]) -> None:
        if t - self._last_t < self._min_period_s - 1e-6:  # (float sums of 0.1 s ticks fall just short)
            return
        self._last_t = t
        row = np.array(
            [[m.angle for m in motors], [m.rmsCurrent for m in motors], [m.statorTemperature for m in motors]]
        )
        with self._lock:
            self._t[self._next] = t
            self._values[self._next] = row
            self._next = (self._next + 1) % self._capacity
            self._count = min(self._count + 1, self._capacity)

    @classmethod
    def long(cls) -> MotorHistory:
        """The last hour at LONG_PERIOD_S."""
        return cls(LONG_HISTORY_S, 1.0 / LONG_PERIOD_S, min_period_s=LONG_PERIOD_S)

    def window(self, seconds: float | None = None) -> HistoryWindow:
        """The samples of the last `seconds` (default: all the history keeps)."""
        seconds = self.seconds if seconds is None else seconds
        with self._lock:
            order = (np.arange(self._count) + self._next - self._count) % self._capacity
            t = self._t[order]
            values = self._values[order]
        if len(t):
            keep = t >= t[-1] - seconds
            t, values = t[keep] - t[-1], values[keep]
        return HistoryWindow(t, values[:, 0], values[:, 1], values[:, 2])
