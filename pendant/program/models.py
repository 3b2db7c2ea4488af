"""A taught program (schema version 2): a table of named waypoints and a tree of steps (pydantic, versioned).

Moves refer to waypoints by name, so many moves can go to one waypoint and re-teaching it moves them all.
Structure steps (Loop, If, Pallet) hold steps of their own; Call runs another program file; a Path step holds
a recorded path's points itself (they are not named waypoints). Version-1 files
(each waypoint inside its move) are migrated on load by `pendant.program.migrate`.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    SerializerFunctionWrapHandler,
    ValidationError,
    model_serializer,
    model_validator,
)
from pydantic_core import ErrorDetails

from pendant.controller.types import (
    DEFAULT_GRIPPER_TIMEOUT_MS,
    GRIPPER_TIMEOUT_MAX_MS,
    MotionType,
    Pose,
    Position,
    SignalLevel,
)
from pendant.program.limits import (
    COMMENT_MAX,
    DEFAULT_APPROACH_MM,
    DEFAULT_INPUT_TIMEOUT_MS,
    DEFAULT_PALLET_NAME,
    DEFAULT_PATH_NAME,
    DEFAULT_PATH_SPEED_MM_S,
    DEFAULT_SPEED_PERCENT,
    MAX_BLEND_MM,
    MAX_LOOP_TIMES,
    MAX_NESTING,
    MAX_OFFSET_MM,
    MAX_PATH_POINTS,
    MAX_PROGRAM_PATH_POINTS,
    MAX_STEPS,
    PATH_SPEED_MAX_MM_S,
    PROGRAM_NAME_MAX,
    SCHEMA_VERSION,
    Degrees,
    GridCount,
    InputPort,
    Millimetres,
    Millis,
    OutputPort,
    Speed,
    WaypointName,
)


class _Frozen(BaseModel):
    # Unknown fields are refused so a typo in a hand-edited file is reported, not silently dropped.
    model_config = ConfigDict(frozen=True, extra="forbid")


class Waypoint(_Frozen):
    """Where the arm was when it was recorded: flange angles (degrees) and TCP position (zero point frame)."""

    name: WaypointName
    pose: Pose
    position: Position


class Frame(StrEnum):
    BASE = "base"  # offset along the base axes: "50 mm above"
    TOOL = "tool"  # offset along the tool's own axes: "50 mm back along the gripper"


class Offset(_Frozen):
    """A relative move's offset from its waypoint: millimetres and degrees (roll, pitch, yaw) in `frame`."""

    x: Millimetres = 0.0
    y: Millimetres = 0.0
    z: Millimetres = 0.0
    rx: Degrees = 0.0
    ry: Degrees = 0.0
    rz: Degrees = 0.0
    frame: Frame = Frame.BASE


class OutputAction(_Frozen):
    """Set a digital output when the arm reaches the waypoint (the API's OutputRobotAction)."""

    target: Literal["output"] = "output"
    port: OutputPort
    value: SignalLevel


class GripperAction(StrEnum):
    OPEN = "open"
    CLOSE = "close"


class GripperAtWaypoint(_Frozen):
    """Open or close the gripper when the arm reaches the waypoint (the API's GripperRobotAction)."""

    target: Literal["gripper"] = "gripper"
    value: GripperAction


WaypointAction = Annotated[OutputAction | GripperAtWaypoint, Field(discriminator="target")]


class MoveStep(_Frozen):
    kind: Literal["move"] = "move"
    waypoint: WaypointName  # a name in Program.waypoints
    motion: MotionType = MotionType.JOINT
    speed: Speed = DEFAULT_SPEED_PERCENT
    offset: Offset | None = None  # a relative move: the waypoint shifted by this
    blend_mm: Annotated[float, Field(ge=0.0, le=MAX_BLEND_MM, allow_inf_nan=False)] = 0.0
    actions: tuple[WaypointAction, ...] = ()  # done on arrival
    # Planned: the path around the cell's obstacles is found when the step runs (pendant.planning), from
    # where the arm is then; only its target is saved. Move J only.
    planned: bool = False

    @model_validator(mode="after")
    def _planned_is_joint(self) -> MoveStep:
        if self.planned and self.motion is not MotionType.JOINT:
            raise ValueError("only a Move J can be planned around obstacles (a Move L goes straight)")
        return self

    @model_serializer(mode="wrap")
    def _without_unplanned(self, handler: SerializerFunctionWrapHandler) -> dict[str, object]:
        """`planned` is saved only when set: a program without planned moves saves as before, and an older
        pendant still opens it."""
        data: dict[str, object] = handler(self)
        if not self.planned:
            data.pop("planned", None)
        return data


class PathPoint(_Frozen):
    """One point of a recorded path: flange angles (degrees) and TCP position (zero point frame), as read."""

    pose: Pose
    position: Position


class PathStep(_Frozen):
    """A recorded path, played back as one blended LINEAR run through its points (README "Path steps").

    `tol_mm` / `tol_deg`: the tolerance the operator set. Half of it went to simplifying the recording (every
    sample within it of the straight segments between the points), the other half is each corner's blend,
    so the played path stays within the tolerance of the recording. The arm first goes to the first point
    by its recorded angles (JOINT, at `speed` percent), then along the path at `velocity_mm_s` at the TCP.
    """

    kind: Literal["path"] = "path"
    name: WaypointName = DEFAULT_PATH_NAME
    points: Annotated[tuple[PathPoint, ...], Field(min_length=2, max_length=MAX_PATH_POINTS)]
    tol_mm: Annotated[float, Field(gt=0.0, le=MAX_OFFSET_MM, allow_inf_nan=False)] = 1.0
    tol_deg: Annotated[float, Field(gt=0.0, le=360.0, allow_inf_nan=False)] = 1.0
    speed: Speed = DEFAULT_SPEED_PERCENT
    velocity_mm_s: Annotated[float, Field(gt=0.0, le=PATH_SPEED_MAX_MM_S, allow_inf_nan=False)] = (
        DEFAULT_PATH_SPEED_MM_S
    )
    recording: Annotated[str, Field(max_length=PROGRAM_NAME_MAX)] | None = None  # its raw recording's file

    @property
    def blend_mm(self) -> float:
        """How far the run may round each corner: the half of the tolerance simplifying did not use."""
        return self.tol_mm / 2.0


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


class CommentStep(_Frozen):
    kind: Literal["comment"] = "comment"
    text: Annotated[str, Field(max_length=COMMENT_MAX)] = ""


class LoopMode(StrEnum):
    TIMES = "times"
    WHILE = "while"  # while DI `port` is at `level` (checked before each pass)
    UNTIL = "until"  # until DI `port` is at `level` (checked before each pass)


class LoopStep(_Frozen):
    kind: Literal["loop"] = "loop"
    mode: LoopMode = LoopMode.TIMES
    times: Annotated[int, Field(ge=0, le=MAX_LOOP_TIMES)] = 2
    port: InputPort = 1
    level: SignalLevel = SignalLevel.HIGH
    body: tuple[Step, ...] = ()


class IfStep(_Frozen):
    """If DI `port` is at `level`, the `then` steps, else the `otherwise` steps."""

    kind: Literal["if"] = "if"
    port: InputPort = 1
    level: SignalLevel = SignalLevel.HIGH
    then: tuple[Step, ...] = ()
    otherwise: tuple[Step, ...] = ()


class CallStep(_Frozen):
    """Run another saved program (its own waypoints); a program may not call itself, even indirectly."""

    kind: Literal["call"] = "call"
    program: Annotated[str, Field(min_length=1, max_length=64)]


class PalletStep(_Frozen):
    """A grid of cells from three taught corners; each pass goes to the next cell and runs `body` there.

    `corners`: the first cell, the last cell of the first row, the last cell of the first column. Each pass:
    above the cell by `approach_mm` (base z), straight down to it, `body` (e.g. the gripper), straight up.
    Layers stack upward by `layer_height_mm`. After the last cell the next pass starts again at the first.
    """

    kind: Literal["pallet"] = "pallet"
    name: WaypointName = DEFAULT_PALLET_NAME
    corners: tuple[WaypointName, WaypointName, WaypointName]
    rows: GridCount = 2
    columns: GridCount = 2
    layers: GridCount = 1
    layer_height_mm: Annotated[float, Field(ge=0.0, le=MAX_OFFSET_MM, allow_inf_nan=False)] = 0.0
    approach_mm: Annotated[float, Field(ge=0.0, le=MAX_OFFSET_MM, allow_inf_nan=False)] = DEFAULT_APPROACH_MM
    speed: Speed = DEFAULT_SPEED_PERCENT
    body: tuple[Step, ...] = ()


Step = Annotated[
    MoveStep
    | GripperStep
    | OutputStep
    | WaitInputStep
    | WaitStep
    | CommentStep
    | LoopStep
    | IfStep
    | CallStep
    | PalletStep
    | PathStep,
    Field(discriminator="kind"),
]
STRUCTURES = (LoopStep, IfStep, PalletStep)
BRANCHES: dict[type, tuple[str, ...]] = {
    LoopStep: ("body",),
    IfStep: ("then", "otherwise"),
    PalletStep: ("body",),
}

for _model in (LoopStep, IfStep, PalletStep):
    _model.model_rebuild()


def children(step: BaseModel) -> list[tuple[str, tuple[Step, ...]]]:
    """A structure step's branches as (field name, steps); [] for any other step."""
    return [(branch, getattr(step, branch)) for branch in BRANCHES.get(type(step), ())]


def walk(steps: tuple[Step, ...]) -> list[Step]:
    """Every step of the tree in list order (a structure before what it holds)."""
    found: list[Step] = []
    for step in steps:
        found.append(step)
        for _, inner in children(step):
            found.extend(walk(inner))
    return found


def _depth(steps: tuple[Step, ...]) -> int:
    return max((1 + max((_depth(inner) for _, inner in children(s)), default=0) for s in steps), default=0)


def referenced_waypoints(step: Step) -> list[str]:
    if isinstance(step, MoveStep):
        return [step.waypoint]
    if isinstance(step, PalletStep):
        return list(step.corners)
    return []


class Program(_Frozen):
    """What a program file holds. `schema_version` lets a newer pendant's files be refused, not misread."""

    schema_version: int = Field(default=SCHEMA_VERSION, ge=1)
    name: Annotated[str, Field(max_length=PROGRAM_NAME_MAX)] = "untitled"
    waypoints: Annotated[tuple[Waypoint, ...], Field(max_length=MAX_STEPS)] = ()
    steps: Annotated[tuple[Step, ...], Field(max_length=MAX_STEPS)] = ()

    @model_validator(mode="after")
    def _references_resolve(self) -> Program:
        names = [w.name for w in self.waypoints]
        duplicates = sorted({n for n in names if names.count(n) > 1})
        if duplicates:
            raise ValueError(f"waypoint names must be unique: {', '.join(map(repr, duplicates))}")
        if _depth(self.steps) > MAX_NESTING:
            raise ValueError(f"steps nest more than {MAX_NESTING} deep")
        every = walk(self.steps)
        if len(every) > MAX_STEPS:  # nested ones count too
            raise ValueError(f"a program has at most {MAX_STEPS} steps")
        if sum(len(s.points) for s in every if isinstance(s, PathStep)) > MAX_PROGRAM_PATH_POINTS:
            raise ValueError(f"recorded paths have at most {MAX_PROGRAM_PATH_POINTS} points in all")
        known = set(names)
        for step in every:
            for name in referenced_waypoints(step):
                if name not in known:
                    raise ValueError(f"a step goes to waypoint {name!r}, which is not in the waypoint table")
        return self

    def waypoint_names(self) -> list[str]:
        return [w.name for w in self.waypoints]

    def waypoint(self, name: str) -> Waypoint:
        for waypoint in self.waypoints:
            if waypoint.name == name:
                return waypoint
        raise KeyError(name)

    def uses_of(self, name: str) -> int:
        """How many steps go to waypoint `name`."""
        return sum(referenced_waypoints(step).count(name) for step in walk(self.steps))


def describe_problems(error: ValidationError, limit: int = 3) -> str:
    """The first `limit` problems pydantic found, as "steps.2.speed: Input should be ..." joined by "; "."""

    def one(issue: ErrorDetails) -> str:
        where = ".".join(str(part) for part in issue["loc"])
        return f"{where}: {issue['msg']}" if where else issue["msg"]

    return "; ".join(one(issue) for issue in error.errors()[:limit])
