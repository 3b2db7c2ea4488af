"""With `--no-ui` there is no page whose refresh loop sees the arm's state: this thread reads the motion
status twice a second and logs its changes (alarms as errors; MOTION_FAILED counted as a motion failure),
so the event log and the metrics hold them in that mode too."""

from __future__ import annotations

import threading

from pendant.controller import ControllerError, MotionStatus
from pendant.controller.errors import ControllerOffline, Emergency, NotResponding
from pendant.controller.protocol import Controller
from pendant.eventlog import EventKind, EventLog
from pendant.monitoring.metrics import PendantMetrics

WATCH_PERIOD_S = 0.5
ALARMS = {MotionStatus.ERROR, MotionStatus.EMERGENCY, MotionStatus.MOTION_FAILED}
OFFLINE = "offline"
NOT_RESPONDING = "not responding"


def read_state(controller: Controller) -> str:
    """The motion status, or why there is none."""
    try:
        return controller.get_motion_status().value
    except Emergency:
        return MotionStatus.EMERGENCY.value
    except NotResponding:
        return NOT_RESPONDING
    except (ControllerOffline, ControllerError):
        return OFFLINE


class StateWatch:
    def __init__(
        self, controller: Controller, events: EventLog, metrics: PendantMetrics | None = None
    ) -> None:
        self._controller = controller
        self._events = events
        self._metrics = metrics
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name="pendant-state-watch", daemon=True)
        self.state = OFFLINE

    def start(self) -> StateWatch:
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)

    def check(self) -> None:
        """One reading: log it if it changed."""
        state = read_state(self._controller)
        if state == self.state:
            return
        before, self.state = self.state, state
        alarm = state in ALARMS or state == NOT_RESPONDING
        kind = EventKind.ERROR if alarm else EventKind.STATE
        self._events.record(kind, "controller", f"{before} → {state}")
        if self._metrics is not None and state == MotionStatus.MOTION_FAILED.value:
            self._metrics.motion_failures.labels("controller").inc()

    def _loop(self) -> None:
        while not self._stop.is_set():
            self.check()
            self._stop.wait(WATCH_PERIOD_S)
