"""Who did what, for the event log: every command from a browser (or refused), jogs, program failures and
the controller's state changes. The pendant's page wires these into its runner, jogger and refresh loop.
With metrics, the same happenings are counted for Prometheus (commands, program runs, motion failures)."""

from __future__ import annotations

import time
from collections.abc import Callable
from concurrent.futures import Future

import viser

from pendant.access.remote import RemoteControl
from pendant.controller import Controller, ControllerError, MotionStatus, PreconditionFailed
from pendant.controller.stops import StopBus
from pendant.eventlog import EventKind, EventLog
from pendant.jog import Jogger, JogRequest
from pendant.jog.arm import JogArm
from pendant.jog.blocked import Touching
from pendant.monitoring import PendantMetrics
from pendant.program import Change, ProgramWorkspace, RunState
from pendant.ui.kit.commands import CommandRefused
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.roles import ControlDesk

_ALARM_STATES = {MotionStatus.ERROR, MotionStatus.EMERGENCY, MotionStatus.MOTION_FAILED}
_RUN_ACTIVE = {RunState.RUNNING, RunState.PAUSED}


class LoggedJogger(Jogger):
    """A Jogger that tells the event log when a jog starts (once per press, not per deadman confirmation),
    and takes its turn with API clients (pendant.access.remote): a press while an API motion is under way is
    refused (PreconditionFailed, once per press), and API commands are refused while the jog is held, so the
    freeze of its release never drops a command a client was told was accepted."""

    def __init__(
        self,
        controller: Controller,
        arm: JogArm,
        *,
        events: EventLog,
        desk: ControlDesk,
        remote: RemoteControl | None = None,
        on_start: Callable[[], None] = lambda: None,
        stops: StopBus | None = None,
        touching: Touching = lambda q: [],
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        super().__init__(controller, arm, clock, on_stop=self._stopped, stops=stops, touching=touching)
        self._events = events
        self._desk = desk
        self._remote = remote
        self._on_start = on_start
        self._refused: JogRequest | None = None  # this press was refused: say so once, not 20 times a second

    def hold(self, request: JogRequest, releases: int | None = None, holder: object = None) -> bool:
        if self.latch_cause(holder) is not None:
            return False  # a stop ended this press: nothing to claim until it is released
        starting = self.active != request
        if starting and self._remote is not None and not self._claim(request):
            return False
        try:
            moved = super().hold(request, releases, holder)
        finally:
            if self._remote is not None and self.active is None:
                self._remote.end_jog()  # it did not start (or stopped at once): the API's turn again
        if starting and moved:
            self._on_start()
            self._events.record(
                EventKind.COMMAND, self._desk.name(self._desk.operator), f"Jog {request.label()}"
            )
        return moved

    def step(self, request: JogRequest) -> bool:
        moved = super().step(request)
        if moved:
            self._events.record(
                EventKind.COMMAND, self._desk.name(self._desk.operator), f"Step {request.label()}"
            )
        return moved

    def release(self, reason: str = "released") -> None:
        self._refused = None
        super().release(reason)

    def _claim(self, request: JogRequest) -> bool:
        """Take the arm from the API for this jog; False (after raising once per press) when refused."""
        assert self._remote is not None
        if self._refused == request:
            return False
        refusal = self._remote.begin_jog(lambda: self._controller.get_motion_status() is MotionStatus.RUNNING)
        if refusal is None:
            self._refused = None
            return True
        self._refused = request
        self._events.record(
            EventKind.REFUSED, self._desk.name(self._desk.operator), f"Jog {request.label()}: {refusal}"
        )
        raise PreconditionFailed(refusal)

    def _stopped(self, label: str, cause: str) -> None:
        if self._remote is not None:
            self._remote.end_jog()  # the freeze has gone out: API commands may follow
        self._events.record(EventKind.COMMAND, "pendant", f"Jog {label} stopped: {cause}")


class ActivityLog:
    """Writes to `events` what the page's commands, programs and the controller do."""

    def __init__(self, events: EventLog, desk: ControlDesk, metrics: PendantMetrics | None = None) -> None:
        self._events = events
        self._desk = desk
        self._metrics = metrics
        if metrics is not None:
            metrics.start_page_at_zero()  # rate() and increase() see the page's first command of each kind
        self._failure_logged: str | None = None
        self._run_state = RunState.IDLE

    def _count(self, label: str, status: str, *, failed: bool) -> None:
        if self._metrics is not None:
            self._metrics.count_command("page", label, status, failed=failed, motion=False)

    def who(self, client: viser.ClientHandle | None) -> str:
        return "pendant" if client is None else self._desk.name(client.client_id)

    def recording(self, client: viser.ClientHandle | None, message: str) -> None:
        """A recording started or stopped in `client`'s Dashboard."""
        self._events.record(EventKind.COMMAND, self.who(client), message)

    def command(
        self,
        label: str,
        client: viser.ClientHandle | None,
        refusal: str | None,
        future: Future[object] | None,
    ) -> None:
        """The CommandRunner's on_submit: a command sent, refused, or (later) failed."""
        who = self.who(client)
        if refusal is not None:
            self._events.record(EventKind.REFUSED, who, f"{label}: {refusal}")
            self._count(label, "refused", failed=True)
            return
        self._events.record(EventKind.COMMAND, who, label)
        if future is None:
            self._count(label, "sent", failed=False)
            return

        def failed(done: Future[object]) -> None:
            error = done.exception() if not done.cancelled() else None
            self._count(label, "sent" if error is None else "failed", failed=error is not None)
            if isinstance(error, ControllerError):
                self._events.record(EventKind.ERROR, who, f"{label} failed: {error.message}")
            elif error is not None and not isinstance(error, CommandRefused):
                self._events.record(EventKind.ERROR, who, f"{label} failed: {error}")

        future.add_done_callback(failed)

    def program_changed(self, programs: ProgramWorkspace, change: Change) -> None:
        """Log a program run's failure once (RUN changes repeat while the failure is shown)."""
        if change is not Change.RUN:
            return
        progress = programs.progress
        if self._metrics is not None and progress.state is not self._run_state:
            if progress.state in _RUN_ACTIVE and self._run_state not in _RUN_ACTIVE:
                self._metrics.program_runs.inc()
            elif progress.state is RunState.FAILED:
                self._metrics.program_failures.inc()
                self._metrics.motion_failures.labels("program").inc()
        self._run_state = progress.state
        if progress.state is not RunState.FAILED and progress.failed_step is None:
            self._failure_logged = None
            return
        if progress.message != self._failure_logged:
            self._failure_logged = progress.message
            self._events.record(EventKind.ERROR, "program", progress.message)

    def state_changed(self, before: Snapshot, after: Snapshot) -> None:
        """A new error message, or a new motion state (alarms logged as errors)."""
        if after.error != before.error and after.error is not None:
            self._events.record(EventKind.ERROR, "controller", after.error)
        if after.motion_status is not None and after.motion_status != before.motion_status:
            was = before.motion_status.value if before.motion_status is not None else "offline"
            kind = EventKind.ERROR if after.motion_status in _ALARM_STATES else EventKind.STATE
            if self._metrics is not None and after.motion_status is MotionStatus.MOTION_FAILED:
                self._metrics.motion_failures.labels("controller").inc()
            self._events.record(kind, "controller", f"{was} → {after.motion_status.value}")
