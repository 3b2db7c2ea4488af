"""Stops heard since a run last (re)started: counted, not flagged, so that a stop arriving while a step is
being started, or while the run is being resumed, is never cleared away by that start."""

from __future__ import annotations

import threading


class HeardStops:
    """`hear` from any thread (a StopBus listener); `since_start` read by the run at every look."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._count = 0
        self._baseline = 0
        self._cause = ""

    def hear(self, cause: str) -> None:
        with self._lock:
            if self._count == self._baseline:  # the first stop since the start is the one the run names
                self._cause = cause
            self._count += 1

    def start(self) -> None:
        """A run starts or resumes: stops heard before now are done with (the arm was still then)."""
        with self._lock:
            self._baseline = self._count
            self._cause = ""

    @property
    def since_start(self) -> bool:
        return self._count != self._baseline

    @property
    def cause(self) -> str:
        return self._cause
