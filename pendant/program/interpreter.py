"""Walking a compiled plan: loops, conditions and pallets as a stack of frames, leaves run by a NodeExecutor.

The stack is the whole execution state, so a paused run continues where it stopped, a failed run can be
resumed at the step that failed (after the operator fixed the cause), and a run can start at any line.
One interpreter serves the page's runner and the headless `pendant run`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from enum import StrEnum

from pendant.program.models import LoopMode
from pendant.program.motion import Interrupted, NodeExecutor, StepFailed
from pendant.program.plan import Branch, Loop, MoveGroup, Node, Pallet, Single


@dataclass
class Frame:
    nodes: tuple[Node, ...]
    index: int = 0
    loop: Loop | None = None  # the loop this frame is a pass of
    passes: int = 0  # finished passes of `loop`
    target: int = 0  # the waypoint to continue at, inside the MoveGroup at `index`


class Outcome(StrEnum):
    FINISHED = "finished"
    STEPPED = "stepped"  # one step done (single-step mode)


class NodeFailed(Exception):
    """A node failed; the stack still points at it, so `run` again retries it."""

    def __init__(
        self, line: int, last_line: int, reason: str, targets: str = "", stopped_by: str = ""
    ) -> None:
        self.line = line
        self.last_line = last_line  # > line when a blended group was refused whole
        self.reason = reason
        self.targets = targets  # that group's waypoints, "A, B, Far"
        self.stopped_by = stopped_by  # the controller stopped the arm itself: a stop, not a failure


@dataclass
class Interpreter:
    plan: tuple[Node, ...]
    loops: int = 1  # whole-program passes; 0: until stopped
    loop: int = 1
    stack: list[Frame] = field(default_factory=list)
    pallet_pass: dict[int, int] = field(default_factory=dict)  # pallet line -> passes so far
    on_line: Callable[[int], None] = lambda line: None

    def __post_init__(self) -> None:
        if not self.stack:
            self.stack = [Frame(self.plan)]

    # --- where we are ----------------------------------------------------------------------------------
    @property
    def line(self) -> int | None:
        """The line about to run (None when the program is done)."""
        if not self.stack:
            return None
        frame = self.stack[-1]
        if frame.index >= len(frame.nodes):
            return None
        node = frame.nodes[frame.index]
        return node.targets[frame.target].line if isinstance(node, MoveGroup) else node.line

    @property
    def place(self) -> int:
        """The line a run that ended here goes on at: the next step, or the loop whose pass just ended
        (its check comes next), or the first line when another whole-program loop follows."""
        for frame in reversed(self.stack):
            if frame.index < len(frame.nodes):
                node = frame.nodes[frame.index]
                return node.targets[frame.target].line if isinstance(node, MoveGroup) else node.line
            if frame.loop is not None:
                return frame.loop.line
        return 0

    @property
    def fraction(self) -> float:
        """0..1 through the run, from the top-level position and the whole-program loop."""
        top = self.stack[0] if self.stack else None
        n = max(len(self.plan), 1)
        index = n if top is None else min(top.index, n)
        if self.loops == 0:
            return index / n
        return ((self.loop - 1) * n + index) / (self.loops * n)

    def start_at(self, line: int) -> None:
        """Begin at the first node at or after `line` (entering loops and branches on the way, their
        conditions not checked; a line inside a pallet starts that pallet's pass)."""
        path = _locate(self.plan, line)
        self.stack = [Frame(self.plan)]
        if path is None:
            self.stack[0].index = len(self.plan)
            return
        for index, target in path[:-1]:
            frame = self.stack[-1]
            frame.index = index
            node = frame.nodes[index]
            if isinstance(node, Loop):
                self.stack.append(Frame(node.body, loop=node))
            elif isinstance(node, Branch):
                self.stack.append(Frame(node.then if target == 0 else node.otherwise))
        self.stack[-1].index, self.stack[-1].target = path[-1]

    def skip(self) -> None:
        """Step over the node the stack points at (the one that failed): the next run starts after it. A
        failed loop check (the frame's end) leaves that loop."""
        frame = self.stack[-1]
        if frame.index >= len(frame.nodes):
            if len(self.stack) > 1:
                self.stack.pop()
                self.stack[-1].index += 1
            return
        node = frame.nodes[frame.index]
        if isinstance(node, MoveGroup) and frame.target + 1 < len(node.targets):
            frame.target += 1
        else:
            frame.index, frame.target = frame.index + 1, 0

    # --- running -------------------------------------------------------------------------------------
    def run(self, executor: NodeExecutor, *, single_step: bool = False) -> Outcome:
        """Execute until the end (or one leaf, in single-step mode). Raises Interrupted (the stack keeps the
        place to continue) or NodeFailed (the stack keeps the failed node)."""
        while True:
            node = self._next(executor)
            if node is None:
                return Outcome.FINISHED
            frame = self.stack[-1]
            line = node.targets[frame.target].line if isinstance(node, MoveGroup) else node.line
            self.on_line(line)
            try:
                leaf = self._execute(node, frame, executor, single_step)
            except StepFailed as failure:
                if isinstance(node, MoveGroup):
                    frame.target = failure.target
                    first = node.targets[failure.target]
                    last = node.targets[-1] if failure.whole else first
                    targets = node.describe(failure.target)
                    raise NodeFailed(
                        first.line, last.line, failure.reason, targets, failure.stopped_by
                    ) from failure
                raise NodeFailed(
                    node.line, node.line, failure.reason, stopped_by=failure.stopped_by
                ) from failure
            except Interrupted as interrupted:
                if isinstance(node, MoveGroup):
                    frame.target = interrupted.target
                raise
            if leaf:
                executor.check()
                if single_step:
                    self._next(executor)  # settle on the next step, so the page can show it
                    return Outcome.STEPPED

    def _execute(self, node: Node, frame: Frame, executor: NodeExecutor, single_step: bool) -> bool:
        """Run or enter `node`; True when a leaf (a move, gripper, IO or wait) was executed."""
        match node:
            case MoveGroup():

                def heading(k: int) -> None:
                    frame.target = k
                    self.on_line(node.targets[k].line)

                last = executor.move(node, frame.target, single_step, heading)
                if last + 1 < len(node.targets):
                    frame.target = last + 1
                else:
                    frame.index, frame.target = frame.index + 1, 0
                return True
            case Single():
                executor.single(node)
                frame.index += 1
                return True
            case Loop():
                if _continues(node, 0, executor):
                    self.stack.append(Frame(node.body, loop=node))
                else:
                    frame.index += 1
            case Branch():
                chosen = node.then if executor.input_is(node.port, node.level) else node.otherwise
                self.stack.append(Frame(chosen))
            case Pallet():
                cell = self.pallet_pass.get(node.line, 0)
                self.pallet_pass[node.line] = cell + 1
                self.stack.append(Frame(node.pass_nodes(cell)))
        return False

    def _next(self, executor: NodeExecutor) -> Node | None:
        """The node to run next, after closing finished frames (repeating loops, the whole program)."""
        while True:
            frame = self.stack[-1]
            if frame.index < len(frame.nodes):
                return frame.nodes[frame.index]
            if len(self.stack) == 1:
                if self.loops == 0 or self.loop < self.loops:
                    self.loop += 1
                    frame.index = 0
                    if not frame.nodes:
                        return None
                    continue
                return None
            if frame.loop is not None and self._loop_continues(frame.loop, frame.passes + 1, executor):
                frame.passes += 1
                frame.index = 0
                continue
            self.stack.pop()
            self.stack[-1].index += 1

    def _loop_continues(self, loop: Loop, passes: int, executor: NodeExecutor) -> bool:
        """The check at the end of a pass: a failed input read fails the Loop's line (a retry re-reads)."""
        try:
            return _continues(loop, passes, executor)
        except StepFailed as failure:
            raise NodeFailed(loop.line, loop.line, failure.reason, stopped_by=failure.stopped_by) from failure


def _continues(loop: Loop, passes: int, executor: NodeExecutor) -> bool:
    """Whether `loop` runs another pass after `passes` finished ones."""
    if not loop.body:
        return False  # an empty loop would spin without moving: nothing to repeat
    if loop.mode is LoopMode.TIMES:
        return passes < loop.times
    executor.check()
    at_level = executor.input_is(loop.port, loop.level)
    return at_level if loop.mode is LoopMode.WHILE else not at_level


def _locate(nodes: tuple[Node, ...], line: int) -> list[tuple[int, int]] | None:
    """Path [(index, branch or target), ...] to the first node at or after `line`, depth first."""
    for index, node in enumerate(nodes):
        if isinstance(node, MoveGroup):
            for k, target in enumerate(node.targets):
                if target.line >= line:
                    return [(index, k)]
            continue
        if node.line >= line:
            return [(index, 0)]
        if isinstance(node, Loop):
            inside = _locate(node.body, line)
            if inside is not None:
                return [(index, 0), *inside]
        elif isinstance(node, Branch):
            for branch, steps in enumerate((node.then, node.otherwise)):
                inside = _locate(steps, line)
                if inside is not None:
                    return [(index, branch), *inside]
        elif isinstance(node, Pallet) and _locate(node.body, line) is not None:
            return [(index, 0)]
    return None
