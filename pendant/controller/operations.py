"""The PULSE operations, declared once: what the routers serve, the docs describe, the body limits bound, the
access guard lets through as stops, the proxy strips down, and the tests check against the routes.

Adding an operation: one `Operation` here, plus its handler in a router (pendant/api/routers). A test
(tests/api/test_operations.py) fails while a route exists that this table does not name, or the other way
round. The table lives at the bottom layer (no FastAPI): pendant.access and pendant.remote read it too, and
pendant.api imports both.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from enum import StrEnum

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


_BODY_LIMITS = {Body.NONE: DEFAULT_BODY_LIMIT, Body.DOCUMENT: DOCUMENT_BODY_LIMIT, Body.RUN: RUN_BODY_LIMIT}


@dataclass(frozen=True)
class Operation:
    """One PULSE operation. `path` is a route template (`/signal/output/{port}`); `schema` names the model of
    its JSON body as documented (`PoseWaypoint`, `PoseWaypoint[]` for a list); `stop`: it only ever stops
    the arm, so it is open to every client in any form; `controller`: False when the pendant answers it
    itself; `in_emergency`: it answers while the arm is in EMERGENCY (SDK 1.8.4 asks why)."""

    method: str
    path: str
    source: Source
    schema: str | None = None
    body: Body = Body.NONE
    stop: bool = False
    controller: bool = True
    in_emergency: bool = False
    pattern: re.Pattern[str] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        regex = re.sub(r"\\\{[^}]+\\\}", "[^/]+", re.escape(self.path))
        object.__setattr__(self, "pattern", re.compile(regex + "/?"))

    @property
    def body_limit(self) -> int:
        return _BODY_LIMITS[self.body]

    def matches(self, method: str, path: str) -> bool:
        return method.upper() == self.method and self.pattern.fullmatch(path) is not None


R, S, SIM = Source.REFERENCE, Source.SDK_1_8, Source.SIMULATOR
DOC, RUN = Body.DOCUMENT, Body.RUN


def _op(method: str, path: str, source: Source, schema: str | None = None, **flags: bool) -> Operation:
    body = Body.NONE if schema is None else RUN if schema.endswith("[]") or "/run" in path else DOC
    return Operation(method, path, source, schema, body, **flags)


OPERATIONS: tuple[Operation, ...] = (
    # The reference guide.
    _op("GET", "/position", R),
    _op("PUT", "/position", R, "PositionWaypoint"),
    _op("PUT", "/positions/run", R, "PositionWaypoint[]"),
    _op("GET", "/pose", R),
    _op("PUT", "/pose", R, "PoseWaypoint"),
    _op("PUT", "/poses/run", R, "PoseWaypoint[]"),
    _op("GET", "/status/motion", R),
    _op("GET", "/status/motors", R),
    _op("GET", "/tool", R),
    _op("POST", "/tool", R, "Tool"),
    _op("GET", "/base", R),
    _op("POST", "/base", R, "Position"),
    _op("GET", "/robot/id", R),
    _op("PUT", "/relax", R),
    _op("PUT", "/freeze", R, stop=True),
    _op("PUT", "/recover", R),
    _op("PUT", "/pack", R),
    _op("PUT", "/gripper/open", R),
    _op("PUT", "/gripper/close", R),
    _op("GET", "/signal/output/{port}", R),
    _op("GET", "/signal/input/{port}", R),
    _op("PUT", "/signal/output/{port}/high", R),
    _op("PUT", "/signal/output/{port}/low", R),
    # Rozum's SDK 1.8.4.
    _op("GET", "/status", S, in_emergency=True),
    _op("GET", "/status/failure", S, in_emergency=True),
    _op("GET", "/robot/info", S),
    _op("GET", "/version/hardware", S),
    _op("GET", "/version/software", S),
    _op("GET", "/version/software/robot", S),
    _op("POST", "/motors-log", S),
    _op("POST", "/gripper/enable", S),
    _op("POST", "/gripper/disable", S),
    _op("GET", "/tool/info", S),
    _op("POST", "/tool/info", S, "ToolInfo"),
    _op("GET", "/tool/shape", S),
    _op("POST", "/tool/shape", S, "ToolShape"),
    _op("GET", "/environment", S),
    _op("PUT", "/environment", S, "Obstacle"),
    _op("DELETE", "/environment", S),
    _op("GET", "/environment/{obstacle}", S),
    _op("DELETE", "/environment/{obstacle}", S),
    _op("POST", "/stop", S, stop=True),
    _op("DELETE", "/stop", S),  # unbinds the stop from the inputs: no stop
    _op("PUT", "/stop/bind/{port}/high", S),
    _op("PUT", "/stop/bind/{port}/low", S),
    _op("PUT", "/zg/on", S),
    _op("PUT", "/zg/off", S),
    _op("PUT", "/jogging", S, "JoggingAcceleration"),
    _op("PUT", "/untwisting/finish", S),
    _op("PUT", "/run/linear/positions", S, "LinearPositions"),
    _op("PUT", "/run/linear/poses", S, "LinearPoses"),
    _op("PUT", "/run/joint/positions", S, "JointPositions"),
    _op("PUT", "/run/joint/poses", S, "JointPoses"),
    # The simulator's own: answered by the pendant whatever the arm's state.
    _op("PUT", "/sim/signal/input/{port}/high", SIM, controller=False),
    _op("PUT", "/sim/signal/input/{port}/low", SIM, controller=False),
    _op("PUT", "/sim/pose", SIM, "Pose", controller=False),
    _op("PUT", "/sim/fault/{fault}", SIM, controller=False),
    _op("GET", "/sim/clock", SIM, controller=False),
    _op("PUT", "/sim/reset", SIM, controller=False),
)

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
