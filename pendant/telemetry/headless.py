"""With `--no-ui` no page samples the arm: while a recording started from the API runs, or the Foxglove live
view is on, this thread reads the motors, the TCP and the motion status at the page's rate and writes them
to both."""

from __future__ import annotations

import threading
import time

from pendant.controller import Controller, ControllerError
from pendant.telemetry.channels import ArmState
from pendant.telemetry.sampler import SAMPLE_HZ, Telemetry

IDLE_CHECK_S = 0.1  # how soon a started recording gets its first sample


class RecordingSampler:
    def __init__(self, controller: Controller, telemetry: Telemetry) -> None:
        self._controller = controller
        self._telemetry = telemetry
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name="pendant-recording-sampler", daemon=True)

    def start(self) -> RecordingSampler:
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)

    def _state(self) -> ArmState:
        try:
            return ArmState(
                tcp=self._controller.get_position(),
                motion_status=self._controller.get_motion_status().value,
            )
        except ControllerError:
            return ArmState()

    def _loop(self) -> None:
        period = 1.0 / SAMPLE_HZ
        due = time.monotonic()
        while not self._stop.is_set():
            if self._telemetry.running is None and self._telemetry.live is None:
                self._stop.wait(IDLE_CHECK_S)
                due = time.monotonic()
                continue
            self._telemetry.sample(self._state())
            # On a fixed beat, not a pause after each sample (which ran at 9.1-9.7 a second, not 10);
            # a late sample (a slow controller) moves the beat rather than bunching samples.
            due = max(due + period, time.monotonic())
            self._stop.wait(due - time.monotonic())
