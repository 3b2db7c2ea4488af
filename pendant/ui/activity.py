"""Who did what, for the event log: every command from a browser (or refused), jogs, program failures and
the controller's state changes. The pendant's page wires these into its runner, jogger and refresh loop."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future

import viser

from pendant.controller import Controller, ControllerError, MotionStatus
from pendant.eventlog import EventKind, EventLog
from pendant.jog import Jogger, JogRequest
from pendant.kinematics import ArmModel
from pendant.program import Change, ProgramWorkspace, RunState
from pendant.ui.commands import CommandRefused
from pendant.ui.roles import ControlDesk
from pendant.ui.snapshot import Snapshot

_ALARM_STATES = {MotionStatus.ERROR, MotionStatus.EMERGENCY, MotionStatus.MOTION_FAILED}


class LoggedJogger(Jogger):
    """A Jogger that tells the event log when a jog starts (once per press, not per deadman confirmation)."""

    def __init__(
        self,
        controller: Controller,
        arm: ArmModel,
        *,
        events: EventLog,
        desk: ControlDesk,
        on_start: Callable[[], None] = lambda: None,
    ) -> None:
        super().__init__(controller, arm, on_stop=self._stopped)
        self._events = events
        self._desk = desk
        self._on_start = on_start

    def hold(self, request: JogRequest, releases: int | None = None) -> bool:
        starting = self.active != request
        moved = super().hold(request, releases)
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

    def _stopped(self, reason: str) -> None:
        self._events.record(EventKind.COMMAND, "pendant", f"Jog stopped ({reason})")


class ActivityLog:
    """Writes to `events` what the page's commands, programs and the controller do."""

    def __init__(self, events: EventLog, desk: ControlDesk) -> None:
        self._events = events
        self._desk = desk
        self._failure_logged: str | None = None

    def who(self, client: viser.ClientHandle | None) -> str:
        return "pendant" if client is None else self._desk.name(client.client_id)

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
            return
        self._events.record(EventKind.COMMAND, who, label)
        if future is None:
            return

        def failed(done: Future[object]) -> None:
            error = done.exception() if not done.cancelled() else None
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
        if progress.state is not RunState.FAILED:
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
            self._events.record(kind, "controller", f"{was} → {after.motion_status.value}")
