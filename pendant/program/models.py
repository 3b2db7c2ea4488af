"""A taught program: named waypoints in move steps, plus gripper, output and wait steps (pydantic, versioned).

A waypoint lives inside the move step that goes to it, so a step list is the whole program: moving a step
up or down moves its waypoint with it, and no step can point at a waypoint that was deleted.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError
from pydantic_core import ErrorDetails

from pendant.controller.types import (
    DEFAULT_GRIPPER_TIMEOUT_MS,
    GRIPPER_TIMEOUT_MAX_MS,
    INPUT_PORTS,
    OUTPUT_PORTS,
    SPEED_MAX,
    SPEED_MIN,
    MotionType,
    Pose,
    Position,
    SignalLevel,
)

SCHEMA_VERSION = 1
DEFAULT_SPEED_PERCENT = 20.0
DEFAULT_INPUT_TIMEOUT_MS = 5000
MAX_WAIT_MS = 3_600_000  # an hour: anything longer is a typo, not a program
WAYPOINT_NAME_MAX = 40
PROGRAM_NAME_MAX = 64
# A program is saved only if it can be loaded back: 2,000 steps of the longest kind (a move, 40-character
# name) take ~1.6 MB as saved, under the 5 MB a file may have (pendant.program.files.MAX_FILE_BYTES).
MAX_STEPS = 2000


class _Frozen(BaseModel):
    # Unknown fields are refused so a typo in a hand-edited file is reported, not silently dropped.
    model_config = ConfigDict(frozen=True, extra="forbid")


WaypointName = Annotated[str, Field(min_length=1, max_length=WAYPOINT_NAME_MAX)]
Speed = Annotated[float, Field(ge=SPEED_MIN, le=SPEED_MAX, allow_inf_nan=False)]
Millis = Annotated[int, Field(ge=0, le=MAX_WAIT_MS)]
OutputPort = Annotated[int, Field(ge=min(OUTPUT_PORTS), le=max(OUTPUT_PORTS))]
InputPort = Annotated[int, Field(ge=min(INPUT_PORTS), le=max(INPUT_PORTS))]


class Waypoint(_Frozen):
    """Where the arm was when it was recorded: flange angles (degrees) and TCP position (zero point frame)."""

    name: WaypointName
    pose: Pose
    position: Position


class MoveStep(_Frozen):
    kind: Literal["move"] = "move"
    waypoint: Waypoint
    motion: MotionType = MotionType.JOINT
    speed: Speed = DEFAULT_SPEED_PERCENT


class GripperAction(StrEnum):
    OPEN = "open"
    CLOSE = "close"


class GripperStep(_Frozen):
    kind: Literal["gripper"] = "gripper"
    action: GripperAction
    timeout_ms: Annotated[int, Field(ge=0, le=GRIPPER_TIMEOUT_MAX_MS)] = DEFAULT_GRIPPER_TIMEOUT_MS


class OutputStep(_Frozen):
    kind: Literal["output"] = "output"
    port: OutputPort
    level: SignalLevel


class WaitInputStep(_Frozen):
    kind: Literal["wait_input"] = "wait_input"
    port: InputPort
    level: SignalLevel
    timeout_ms: Millis = DEFAULT_INPUT_TIMEOUT_MS


class WaitStep(_Frozen):
    kind: Literal["wait"] = "wait"
    ms: Millis


Step = Annotated[MoveStep | GripperStep | OutputStep | WaitInputStep | WaitStep, Field(discriminator="kind")]


class Program(_Frozen):
    """What a program file holds. `schema_version` lets a newer pendant's files be refused, not misread."""

    schema_version: int = Field(default=SCHEMA_VERSION, ge=1)  # files start at version 1
    name: Annotated[str, Field(max_length=PROGRAM_NAME_MAX)] = "untitled"
    steps: Annotated[tuple[Step, ...], Field(max_length=MAX_STEPS)] = ()

    def waypoint_names(self) -> list[str]:
        return [step.waypoint.name for step in self.steps if isinstance(step, MoveStep)]


def describe_problems(error: ValidationError, limit: int = 3) -> str:
    """The first `limit` problems pydantic found, as "steps.2.speed: Input should be ..." joined by "; "."""

    def one(issue: ErrorDetails) -> str:
        where = ".".join(str(part) for part in issue["loc"])
        return f"{where}: {issue['msg']}" if where else issue["msg"]

    return "; ".join(one(issue) for issue in error.errors()[:limit])


def describe_step(step: Step) -> str:
    """One line an operator reads in the step list: "Move J to P1 @ 20%", "Wait DI2 HIGH (5000 ms)"."""
    match step:
        case MoveStep():
            letter = "J" if step.motion is MotionType.JOINT else "L"
            return f"Move {letter} to {step.waypoint.name} @ {step.speed:g}%"
        case GripperStep():
            return f"Gripper {step.action.value} ({step.timeout_ms} ms)"
        case OutputStep():
            return f"Set DO{step.port} {step.level.value}"
        case WaitInputStep():
            return f"Wait DI{step.port} {step.level.value} (timeout {step.timeout_ms} ms)"
        case WaitStep():
            return f"Wait {step.ms} ms"
    raise TypeError(f"not a step: {step!r}")
