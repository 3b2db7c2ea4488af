"""A program compiled for execution: waypoints resolved, relative moves and pallet cells computed, called
programs inlined, consecutive moves grouped into one blended call. The runner and the exported script both
execute this plan, so they move the arm the same way.

Every node carries the step-list line (0-based, depth first) it came from, so progress and failures name the
step the operator sees; the steps of a called program report the Call's line.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from pendant.controller.types import (
    MAX_RUN_WAYPOINTS,
    SPEED_MAX,
    MotionParams,
    MotionType,
    Pose,
    Position,
    SignalLevel,
)
from pendant.program.describe import describe_step
from pendant.program.geometry import MM, lifted, offset_position, pallet_cells
from pendant.program.models import (
    CallStep,
    CommentStep,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    OutputStep,
    PalletStep,
    PathStep,
    Program,
    Step,
    WaitInputStep,
    WaitStep,
    Waypoint,
    WaypointAction,
    children,
)

# A blended call the controller accepts in one request; longer runs of moves are split.
MAX_GROUP_TARGETS = MAX_RUN_WAYPOINTS
MAX_CALL_DEPTH = 8


class PlanError(Exception):
    """The program cannot be executed as it is (a missing or recursive Call); `str()` says which step."""


@dataclass(frozen=True)
class Target:
    """One waypoint of a blended move: by angles (an absolute JOINT move, `pose` set; `position` is where
    it was recorded) or to a TCP position (`pose` None)."""

    line: int
    name: str
    pose: Pose | None
    position: Position | None
    blend_mm: float = 0.0
    actions: tuple[WaypointAction, ...] = ()

    def expect_pose(self) -> Pose:
        """The angles of a target of a by-angles group (every one of those has them)."""
        assert self.pose is not None, f"{self.name} has no angles"
        return self.pose

    def expect_position(self) -> Position:
        """The TCP position of a target of a position group (every one of those has it)."""
        assert self.position is not None, f"{self.name} has no TCP position"
        return self.position


@dataclass(frozen=True)
class MoveGroup:
    """Moves run as one /poses/run (targets with angles) or /positions/run: the arm blends through them.

    `velocity_m_s` set: a recorded path (a Path step), LINEAR at that TCP speed, each corner rounded within
    its target's blend, sent as one /run/linear/positions (pendant.program.blended); never joined with
    other moves.

    `planned`: one planned Move J; its path around the obstacles is found when it runs, never joined
    with other moves."""

    targets: tuple[Target, ...]
    motion: MotionType
    speed: float
    velocity_m_s: float | None = None
    planned: bool = False

    @property
    def path(self) -> bool:
        return self.velocity_m_s is not None

    @property
    def line(self) -> int:
        return self.targets[0].line

    @property
    def by_angles(self) -> bool:
        return self.targets[0].pose is not None

    @property
    def params(self) -> MotionParams:
        if self.velocity_m_s is not None:  # the joints as fast as they go, the TCP at the path's speed
            return MotionParams(speed=SPEED_MAX, motion_type=self.motion, tcp_max_velocity=self.velocity_m_s)
        return MotionParams(speed=self.speed, motion_type=self.motion)

    def describe(self, start: int = 0) -> str:
        return ", ".join(t.name for t in self.targets[start:])


@dataclass(frozen=True)
class Single:
    """A gripper, output or wait step, executed on its own."""

    line: int
    step: GripperStep | OutputStep | WaitInputStep | WaitStep

    def describe(self, start: int = 0) -> str:
        return describe_step(self.step)


@dataclass(frozen=True)
class Loop:
    line: int
    mode: LoopMode
    times: int
    port: int
    level: SignalLevel
    body: tuple[Node, ...]

    def describe(self, start: int = 0) -> str:
        return "loop"


@dataclass(frozen=True)
class Branch:
    line: int
    port: int
    level: SignalLevel
    then: tuple[Node, ...]
    otherwise: tuple[Node, ...]

    def describe(self, start: int = 0) -> str:
        return "if"


@dataclass(frozen=True)
class Pallet:
    line: int
    name: str
    cells: tuple[Position, ...]
    approach_m: float
    speed: float
    body: tuple[Node, ...]

    def describe(self, start: int = 0) -> str:
        return f"pallet {self.name}"

    def pass_nodes(self, cell: int) -> tuple[Node, ...]:
        """One pass at cell `cell` (wrapping): above it, down to it, the body, back up."""
        index = cell % len(self.cells)
        at = self.cells[index]
        above = lifted(at, self.approach_m)
        name = f"{self.name}[{index + 1}]"

        def go(position: Position, label: str, motion: MotionType) -> MoveGroup:
            return MoveGroup((Target(self.line, label, None, position),), motion, self.speed)

        return (
            go(above, f"above {name}", MotionType.JOINT),
            go(at, name, MotionType.LINEAR),
            *self.body,
            go(above, f"above {name}", MotionType.LINEAR),
        )


Node = MoveGroup | Single | Loop | Branch | Pallet
Loader = Callable[[str], Program]


@dataclass
class _Compiler:
    load: Loader | None
    blend: bool
    actions_in_path: bool
    calls: list[str] = field(default_factory=list)
    tables: dict[int, dict[str, Waypoint]] = field(default_factory=dict)
    next_line: int = 0

    def program(self, program: Program, steps: tuple[Step, ...], line: int | None) -> tuple[Node, ...]:
        """Nodes of `steps`; `line` fixed: every node reports that line (a called program's steps)."""
        nodes: list[Node] = []
        for step in steps:
            here = self.next_line if line is None else line
            if line is None:
                self.next_line += 1
            node = self.step(program, step, here, line)
            if isinstance(node, MoveGroup) and nodes and self._joins(nodes[-1], node):
                last = nodes[-1]
                assert isinstance(last, MoveGroup)
                nodes[-1] = MoveGroup((*last.targets, *node.targets), last.motion, last.speed)
            elif isinstance(node, tuple):
                nodes.extend(node)
            elif node is not None:
                nodes.append(node)
        return tuple(nodes)

    def table(self, program: Program) -> dict[str, Waypoint]:
        """The program's waypoints by name (built once per program: a plan may have thousands of moves)."""
        key = id(program)
        if key not in self.tables:
            self.tables[key] = {w.name: w for w in program.waypoints}
        return self.tables[key]

    def _joins(self, last: Node, node: MoveGroup) -> bool:
        # Today's controllers run actions only after a stop: a waypoint with actions ends its group.
        return (
            self.blend
            and isinstance(last, MoveGroup)
            and not last.path
            and not node.path
            and not last.planned
            and not node.planned
            and last.motion is node.motion
            and last.speed == node.speed
            and last.by_angles == node.by_angles
            and (self.actions_in_path or not last.targets[-1].actions)
            and len(last.targets) < MAX_GROUP_TARGETS
        )

    def step(
        self, program: Program, step: Step, line: int, fixed: int | None
    ) -> Node | tuple[Node, ...] | None:
        def inner(steps: tuple[Step, ...]) -> tuple[Node, ...]:
            return self.program(program, steps, fixed)

        match step:
            case MoveStep():
                target = self.target(program, step, line)
                return MoveGroup((target,), step.motion, step.speed, planned=step.planned)
            case GripperStep() | OutputStep() | WaitInputStep() | WaitStep():
                return Single(line, step)
            case CommentStep():
                return None
            case LoopStep():
                return Loop(line, step.mode, step.times, step.port, step.level, inner(step.body))
            case IfStep():
                return Branch(line, step.port, step.level, inner(step.then), inner(step.otherwise))
            case PalletStep():
                table = self.table(program)
                first, row_end, column_end = (table[name].position for name in step.corners)
                corners = (first, row_end, column_end)
                cells = pallet_cells(corners, step.rows, step.columns, step.layers, step.layer_height_mm * MM)
                return Pallet(
                    line, step.name, tuple(cells), step.approach_mm * MM, step.speed, inner(step.body)
                )
            case CallStep():
                return self.call(step, line)
            case PathStep():
                return path_nodes(step, line)
        raise TypeError(f"not a step: {step!r}")

    def target(self, program: Program, step: MoveStep, line: int) -> Target:
        waypoint = self.table(program)[step.waypoint]
        if step.offset is None and step.motion is MotionType.JOINT:
            return Target(line, step.waypoint, waypoint.pose, waypoint.position, step.blend_mm, step.actions)
        position = (
            waypoint.position if step.offset is None else offset_position(waypoint.position, step.offset)
        )
        name = step.waypoint if step.offset is None else f"{step.waypoint}+offset"
        return Target(line, name, None, position, step.blend_mm, step.actions)

    def call(self, step: CallStep, line: int) -> tuple[Node, ...]:
        if self.load is None:
            raise PlanError(f"Step {line + 1} (Call {step.program}): no programs folder to load it from")
        if step.program in self.calls:
            chain = " -> ".join([*self.calls, step.program])
            raise PlanError(f"Step {line + 1} (Call {step.program}) calls itself: {chain}")
        if len(self.calls) >= MAX_CALL_DEPTH:
            raise PlanError(f"Step {line + 1} (Call {step.program}): calls nest deeper than {MAX_CALL_DEPTH}")
        try:
            called = self.load(step.program)
        except Exception as error:  # a missing or refused file: say which step needs it
            raise PlanError(f"Step {line + 1} (Call {step.program}): {error}") from error
        self.calls.append(step.program)
        try:
            return self.program(called, called.steps, line)
        finally:
            self.calls.pop()


def path_nodes(step: PathStep, line: int) -> tuple[MoveGroup, ...]:
    """A Path step: to its first point by the recorded angles (JOINT, stopping there), then one blended
    LINEAR run through the others (split at the controller's run limit)."""
    names = [f"{step.name}[{k + 1}]" for k in range(len(step.points))]
    first = step.points[0]
    approach = MoveGroup((Target(line, names[0], first.pose, first.position),), MotionType.JOINT, step.speed)
    targets = [
        Target(line, name, None, point.position, step.blend_mm)
        for name, point in zip(names[1:], step.points[1:], strict=True)
    ]
    velocity = step.velocity_mm_s * MM
    runs = tuple(
        MoveGroup(tuple(targets[i : i + MAX_GROUP_TARGETS]), MotionType.LINEAR, step.speed, velocity)
        for i in range(0, len(targets), MAX_GROUP_TARGETS)
    )
    return (approach, *runs)


def compile_program(
    program: Program, load: Loader | None = None, *, blend: bool = True, actions_in_path: bool = False
) -> tuple[Node, ...]:
    """The execution plan of `program`; `load` opens the programs that Call steps name. `actions_in_path`:
    the controller takes waypoint actions inside a blended request, so they do not end a group."""
    compiler = _Compiler(load, blend, actions_in_path, calls=[program.name])
    return compiler.program(program, program.steps, None)


def line_count(program: Program) -> int:
    def count(steps: tuple[Step, ...]) -> int:
        return sum(1 + sum(count(inner) for _, inner in children(s)) for s in steps)

    return count(program.steps)
