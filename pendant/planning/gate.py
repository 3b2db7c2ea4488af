"""The Run gate: on a real arm, a program runs only after a passing pre-flight of it as it is now.

A fingerprint covers the program (and the programs it calls), the cell (obstacles, tool shape) and the tool,
so any edit or change of the cell or tool needs a new check. The operator may run without one: the
override is logged with who gave it. On the simulator the gate is open (Check is offered, not required).
"""

from __future__ import annotations

import hashlib
import json
import threading
from collections.abc import Callable
from dataclasses import dataclass

from pendant.controller import Controller
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.errors import Unsupported
from pendant.controller.types import Tool
from pendant.eventlog import EventKind, EventLog
from pendant.planning.report import PreflightReport
from pendant.program.models import CallStep, Program, walk
from pendant.program.plan import MAX_CALL_DEPTH, Loader

MSG_CHECK_FIRST = "Check the program first: on the real arm a program runs after a passing pre-flight"
MSG_FAILED = "The last pre-flight of this program failed: {summary}"


def fingerprint(
    program: Program,
    obstacles: list[Obstacle],
    tool_shape: ToolShape,
    tool: Tool,
    load: Loader | None = None,
) -> str:
    """A digest of what a pre-flight's result depends on (the arm's pose and IO aside)."""
    digest = hashlib.sha256()

    def add(value: object) -> None:
        digest.update(json.dumps(value, sort_keys=True, default=str).encode())

    add(program.model_dump(mode="json"))
    add([o.model_dump(mode="json") for o in obstacles])
    add(tool_shape.model_dump(mode="json"))
    add(tool.model_dump(mode="json"))
    _add_called(program, load, add, depth=0, seen=set())
    return digest.hexdigest()


def _add_called(
    program: Program, load: Loader | None, add: Callable[[object], None], depth: int, seen: set[str]
) -> None:
    if load is None or depth >= MAX_CALL_DEPTH:
        return
    for step in walk(program.steps):
        if isinstance(step, CallStep) and step.program not in seen:
            seen.add(step.program)
            try:
                called = load(step.program)
            except Exception:  # a missing program: the pre-flight itself refuses it
                add(f"missing {step.program}")
                continue
            add(called.model_dump(mode="json"))
            _add_called(called, load, add, depth + 1, seen)


def current_fingerprint(program: Program, controller: Controller, load: Loader | None = None) -> str:
    """The fingerprint with the controller's cell and tool as they are now (GET requests only)."""
    try:
        obstacles, shape = controller.get_obstacles(), controller.get_tool_shape()
    except Unsupported:
        obstacles, shape = [], ToolShape(shape=[])
    return fingerprint(program, obstacles, shape, controller.get_tool(), load)


@dataclass(frozen=True)
class Decision:
    allowed: bool
    reason: str  # why not (or how it was allowed)


class RunGate:
    """Whether Run may start. `required`: a real arm (proxy mode); else always allowed."""

    def __init__(self, required: bool, events: EventLog | None = None) -> None:
        self.required = required
        self._events = events
        self._lock = threading.Lock()
        self._checked: tuple[str, PreflightReport] | None = None  # the last pre-flight
        self._overridden: str | None = None

    def record_check(self, print_: str, report: PreflightReport) -> None:
        with self._lock:
            self._checked = (print_, report)

    def last_check(self, print_: str) -> PreflightReport | None:
        """The last pre-flight's report if it was of this very fingerprint."""
        with self._lock:
            checked = self._checked
        return checked[1] if checked is not None and checked[0] == print_ else None

    def override(self, print_: str, who: str, program: str) -> None:
        """Let this fingerprint run without a passing pre-flight; the event log says who decided."""
        with self._lock:
            self._overridden = print_
        if self._events is not None:
            self._events.record(
                EventKind.COMMAND, who, f"Run of {program!r} without a passing pre-flight: overridden"
            )

    def decide(self, print_: str) -> Decision:
        if not self.required:
            return Decision(True, "simulator: the pre-flight is offered, not required")
        with self._lock:
            overridden = self._overridden == print_
        if overridden:
            return Decision(True, "overridden by the operator")
        report = self.last_check(print_)
        if report is None:
            return Decision(False, MSG_CHECK_FIRST)
        if not report.ok:
            return Decision(False, MSG_FAILED.format(summary=report.summary))
        return Decision(True, "pre-flight passed")
