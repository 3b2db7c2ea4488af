"""One reading of the motors for everybody: the refresh loop calls `sample()` a few times a second."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from pendant.controller import Controller, ControllerError
from pendant.controller.types import MotorStatus
from pendant.telemetry.history import MotorHistory
from pendant.telemetry.recorder import CsvRecorder

SAMPLE_HZ = 10.0


class Telemetry:
    """Reads GET /status/motors once per call and feeds the shared history and the recorder."""

    def __init__(self, controller: Controller, now: Callable[[], float] = time.monotonic) -> None:
        self._controller = controller
        self._now = now
        self.history = MotorHistory()
        self.recorder = CsvRecorder()
        self.latest: list[MotorStatus] | None = None
        self.seq = 0  # counts samples: the dashboard redraws only when it moved
        self._lock = threading.Lock()

    def sample(self) -> list[MotorStatus] | None:
        """Read the motors once; None (and nothing recorded) when the controller cannot answer."""
        try:
            motors = self._controller.get_motors()
        except ControllerError:
            self.latest = None
            return None
        now = self._now()
        with self._lock:
            self.history.append(now, motors)
            self.recorder.record(now, motors)
            self.latest = motors
            self.seq += 1
        return motors

    def start_recording(self) -> None:
        self.recorder.start(self._now())

    def stop_recording(self) -> int:
        return self.recorder.stop()
