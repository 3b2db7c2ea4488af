"""How a program is executed: consecutive moves of one type and speed become one blended call.

A blended call holds at most MAX_RUN_WAYPOINTS moves, the most the controller plans at once (more is refused
with 412 before the arm moves): a longer stretch becomes several calls, one after the other.

The runner and the exported script both execute this grouping, so they move the arm the same way.
"""

from __future__ import annotations

from dataclasses import dataclass

from pendant.controller.types import MAX_RUN_WAYPOINTS, MotionParams, MotionType
from pendant.program.models import MoveStep, Step


@dataclass(frozen=True)
class MoveGroup:
    """Moves run as one /poses/run (JOINT) or /positions/run (LINEAR): the arm blends through them."""

    first: int  # index of the first step in the program
    moves: tuple[MoveStep, ...]

    @property
    def indices(self) -> range:
        return range(self.first, self.first + len(self.moves))

    @property
    def motion(self) -> MotionType:
        return self.moves[0].motion

    @property
    def params(self) -> MotionParams:
        return MotionParams(speed=self.moves[0].speed, motion_type=self.motion)


@dataclass(frozen=True)
class SingleStep:
    """Any other step (gripper, output, waits), executed on its own."""

    index: int
    step: Step

    @property
    def indices(self) -> range:
        return range(self.index, self.index + 1)


Segment = MoveGroup | SingleStep


def plan_segments(steps: tuple[Step, ...] | list[Step], *, blend: bool = True) -> list[Segment]:
    """The program's steps in execution order; with `blend=False` every move is its own segment."""
    segments: list[Segment] = []
    for index, step in enumerate(steps):
        if isinstance(step, MoveStep):
            last = segments[-1] if segments else None
            if (
                blend
                and isinstance(last, MoveGroup)
                and last.motion is step.motion
                and last.moves[0].speed == step.speed
                and len(last.moves) < MAX_RUN_WAYPOINTS
            ):
                segments[-1] = MoveGroup(last.first, (*last.moves, step))
            else:
                segments.append(MoveGroup(index, (step,)))
        else:
            segments.append(SingleStep(index, step))
    return segments
