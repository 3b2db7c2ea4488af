"""The PULSE operations, declared once. Each row drives what it describes: the route the API serves
(method, path, the documented request body and answer: pendant.api.operation_route), the body's size limit,
whether the access guard opens it to everyone as a stop, how the proxy forwards it
(`Operation.forwarding`), and the remote client's request and how it reads the answer
(`RemoteController.call`).

Adding an operation: one row here, its handler in a router (pendant/api/routers, registered with
`serve(router, "METHOD /path")`) and the simulator's code behind it (docs/development.md, "Adding an
operation"). The API refuses to start while a row has no route or a route no row (create_app), and
tests/api/test_operations.py fails while a served route's method, path or models differ from its row's, or
the remote client cannot read a row's real answer as the row types it. The table lives at the bottom
layer (no FastAPI): pendant.access and pendant.remote read it too, and pendant.api imports both.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from enum import StrEnum
from typing import Any, get_args, get_origin

from pendant.controller.cell_types import Obstacle, ToolInfo, ToolShape
from pendant.controller.system_types import (
    Failure,
    JoggingAcceleration,
    JointPoses,
    JointPositions,
    LinearPoses,
    LinearPositions,
    PoseTimestamp,
    PoseWaypoint,
    PositionTimestamp,
    PositionWaypoint,
    RobotInfo,
    SystemState,
    Version,
)
from pendant.controller.types import (
    MotionStatus,
    MotorStatus,
    Pose,
    Position,
    RecoverResult,
    SignalLevel,
    Tool,
)

KIB = 1024
# One pose, position, tool, obstacle or jog: a few hundred bytes; 8 KiB leaves room for pretty-printed JSON.
DOCUMENT_BODY_LIMIT = 8 * KIB
# A run: at most 100 waypoints (the controller's own limit), about 300 bytes each when pretty-printed.
RUN_BODY_LIMIT = 128 * KIB
# Anything else (reads and commands without a body, unknown paths): nothing is expected.
DEFAULT_BODY_LIMIT = 1 * KIB


class Source(StrEnum):
    """Where an operation comes from."""

    REFERENCE = "reference"  # the controller's API reference guide
    SDK_1_8 = "sdk-1.8"  # Rozum's SDK 1.8.4 (pulse-api / pdhttp), beyond the guide
    SIMULATOR = "simulator"  # the pendant's simulator only (/sim/*)


class Body(StrEnum):
    """How large a JSON body an operation takes."""

    NONE = "none"
    DOCUMENT = "document"
    RUN = "run"


READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})  # what the proxy forwards as a read, outside the table


class Reply(StrEnum):
    """What a 200 answer carries."""

    EMPTY = "empty"  # nothing (the reference guide's commands)
    TEXT = (
        "text"  # a string: a JSON string literal in text/plain (a status, a level, the controller's message)
    )
    JSON = "json"  # a JSON document


class Forwarding(StrEnum):
    """How the proxy forwards a request to the controller (pendant.remote.proxy)."""

    READ = "read"  # the short read timeout, a GET retried once on a fresh connection
    COMMAND = "command"  # sent once, the long command timeout; an answer lost is 504 "may have run"
    STOP = "stop"  # a command sent bare (no body, no page headers), ahead of queued requests


_BODY_LIMITS = {Body.NONE: DEFAULT_BODY_LIMIT, Body.DOCUMENT: DOCUMENT_BODY_LIMIT, Body.RUN: RUN_BODY_LIMIT}


@dataclass(frozen=True)
class Operation:
    """One PULSE operation. `path` is a route template (`/signal/output/{port}`); `schema` names the model of
    its JSON body as documented (`PoseWaypoint`, `PoseWaypoint[]` for a list), `request` is that body's type;
    `reply` what a 200 carries and `result` its type (a model, `list[...]`, or for text a `str` enum);
    `stop`: it only ever stops the arm, so it is open to every client in any form; `controller`: False when
    the pendant answers it itself; `in_emergency`: it answers while the arm is in EMERGENCY (SDK 1.8.4 asks
    why)."""

    method: str
    path: str
    source: Source
    schema: str | None = None
    body: Body = Body.NONE
    stop: bool = False
    controller: bool = True
    in_emergency: bool = False
    request: Any = None
    reply: Reply = Reply.EMPTY
    result: Any = None
    pattern: re.Pattern[str] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        regex = re.sub(r"\\\{[^}]+\\\}", "[^/]+", re.escape(self.path))
        object.__setattr__(self, "pattern", re.compile(regex + "/?"))

    @property
    def key(self) -> str:
        """`METHOD /path`: how routers and the remote client name the row."""
        return f"{self.method} {self.path}"

    @property
    def forwarding(self) -> Forwarding:
        if self.stop:
            return Forwarding.STOP
        return Forwarding.READ if self.method == "GET" else Forwarding.COMMAND

    @property
    def body_limit(self) -> int:
        return _BODY_LIMITS[self.body]

    def matches(self, method: str, path: str) -> bool:
        return method.upper() == self.method and self.pattern.fullmatch(path) is not None


DOC, RUN = Body.DOCUMENT, Body.RUN
R, S, SIM = Source.REFERENCE, Source.SDK_1_8, Source.SIMULATOR
EMPTY, TEXT, JSON = Reply.EMPTY, Reply.TEXT, Reply.JSON


def _op(
    key: str,
    source: Source,
    request: Any = None,
    reply: Reply = EMPTY,
    result: Any = None,
    *,
    schema: str | None = None,
    **flags: bool,
) -> Operation:
    method, _, path = key.partition(" ")
    if request is not None and schema is None:
        schema = _schema_name(request)
    body = Body.NONE if schema is None else RUN if schema.endswith("[]") or "/run" in path else DOC
    if reply is TEXT and result is None:
        result = str  # the controller's message
    return Operation(method, path, source, schema, body, request=request, reply=reply, result=result, **flags)


def _schema_name(request: Any) -> str:
    if get_origin(request) is list:
        return f"{get_args(request)[0].__name__}[]"
    return str(request.__name__)


OPERATIONS: tuple[Operation, ...] = (
    # The reference guide.
    _op("GET /position", R, None, JSON, PositionTimestamp),
    _op("PUT /position", R, PositionWaypoint, JSON, Position),
    _op("PUT /positions/run", R, list[PositionWaypoint]),
    _op("GET /pose", R, None, JSON, PoseTimestamp),
    _op("PUT /pose", R, PoseWaypoint),
    _op("PUT /poses/run", R, list[PoseWaypoint]),
    _op("GET /status/motion", R, None, TEXT, MotionStatus),
    _op("GET /status/motors", R, None, JSON, list[MotorStatus]),
    _op("GET /tool", R, None, JSON, Tool),
    _op("POST /tool", R, Tool, JSON, Tool),
    _op("GET /base", R, None, JSON, Position),
    _op("POST /base", R, Position, JSON, Position),
    _op("GET /robot/id", R, None, TEXT),
    _op("PUT /relax", R),
    _op("PUT /freeze", R, stop=True),
    _op("PUT /recover", R, None, TEXT, RecoverResult),
    _op("PUT /pack", R),
    _op("PUT /gripper/open", R),
    _op("PUT /gripper/close", R),
    _op("GET /signal/output/{port}", R, None, TEXT, SignalLevel),
    _op("GET /signal/input/{port}", R, None, TEXT, SignalLevel),
    _op("PUT /signal/output/{port}/high", R),
    _op("PUT /signal/output/{port}/low", R),
    # Rozum's SDK 1.8.4.
    _op("GET /status", S, None, TEXT, SystemState, in_emergency=True),  # a JSON string, as the SDK has it
    _op("GET /status/failure", S, None, JSON, list[Failure], in_emergency=True),
    _op("GET /robot/info", S, None, JSON, RobotInfo),
    _op("GET /version/hardware", S, None, JSON, Version),
    _op("GET /version/software", S, None, JSON, Version),
    _op("GET /version/software/robot", S, None, TEXT),
    _op("POST /motors-log", S, None, JSON, int),
    _op("POST /gripper/enable", S, None, TEXT),
    _op("POST /gripper/disable", S, None, TEXT),
    _op("GET /tool/info", S, None, JSON, ToolInfo),
    _op("POST /tool/info", S, ToolInfo, JSON, ToolInfo),
    _op("GET /tool/shape", S, None, JSON, ToolShape),
    _op("POST /tool/shape", S, ToolShape, JSON, ToolShape),
    _op("GET /environment", S, None, JSON, list[Obstacle]),
    _op("PUT /environment", S, Obstacle, TEXT, schema="Obstacle"),
    _op("DELETE /environment", S, None, TEXT),
    _op("GET /environment/{obstacle}", S, None, JSON, Obstacle),
    _op("DELETE /environment/{obstacle}", S, None, TEXT),
    _op("POST /stop", S, None, TEXT, stop=True),
    _op("DELETE /stop", S, None, TEXT),  # unbinds the stop from the inputs: no stop
    _op("PUT /stop/bind/{port}/high", S, None, TEXT),
    _op("PUT /stop/bind/{port}/low", S, None, TEXT),
    _op("PUT /zg/on", S, None, TEXT),
    _op("PUT /zg/off", S, None, TEXT),
    _op("PUT /jogging", S, JoggingAcceleration, TEXT),
    _op("PUT /untwisting/finish", S, None, TEXT),
    _op("PUT /run/linear/positions", S, LinearPositions, TEXT),
    _op("PUT /run/linear/poses", S, LinearPoses, TEXT),
    _op("PUT /run/joint/positions", S, JointPositions, TEXT),
    _op("PUT /run/joint/poses", S, JointPoses, TEXT),
    # The simulator's own: answered by the pendant whatever the arm's state.
    _op("PUT /sim/signal/input/{port}/high", SIM, controller=False),
    _op("PUT /sim/signal/input/{port}/low", SIM, controller=False),
    _op("PUT /sim/pose", SIM, Pose, controller=False),
    _op("PUT /sim/fault/{fault}", SIM, controller=False),
    _op("GET /sim/clock", SIM, None, JSON, dict[str, Any], controller=False),
    _op("PUT /sim/reset", SIM, controller=False),
)
BY_KEY: dict[str, Operation] = {op.key: op for op in OPERATIONS}

STOPS: frozenset[tuple[str, str]] = frozenset((op.method, op.path) for op in OPERATIONS if op.stop)
BODY_LIMITS: dict[tuple[str, str], int] = {
    (op.method, op.path): op.body_limit for op in OPERATIONS if op.body is not Body.NONE
}
ANSWER_IN_EMERGENCY: frozenset[str] = frozenset(op.path for op in OPERATIONS if op.in_emergency)


def find_operation(method: str, path: str) -> Operation | None:
    """The operation `method path` asks for (path without its query), or None for no PULSE operation."""
    return next((op for op in OPERATIONS if op.matches(method, path)), None)


def is_stop(method: str, path: str) -> bool:
    """`PUT /freeze` and `POST /stop`: the requests that only ever stop the arm."""
    return (method.upper(), path.rstrip("/")) in STOPS


def operation(key: str) -> Operation:
    """The row named `METHOD /path` (a template: `PUT /signal/output/{port}/high`); KeyError for none."""
    return BY_KEY[key]


def forwarding(method: str, path: str) -> Forwarding:
    """How the proxy forwards `method path`: as its row says, or by its method outside the table."""
    if is_stop(method, path):  # "/freeze/" too
        return Forwarding.STOP
    found = find_operation(method, path)
    if found is not None:
        return found.forwarding
    return Forwarding.READ if method.upper() in READ_METHODS else Forwarding.COMMAND
