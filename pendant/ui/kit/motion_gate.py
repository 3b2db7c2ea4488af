"""When the page refuses a motion, and how it says why (the command runner's motion_block and explain)."""

from __future__ import annotations

from collections.abc import Callable

from pendant.controller import MotionStatus
from pendant.program import ProgramWorkspace
from pendant.program.runner import RunState

PROGRAM_RUNNING = "A program is running: Pause or Stop it first"


def program_block(programs: ProgramWorkspace) -> Callable[[], str | None]:
    """The page moves the arm only when no program does (Freeze, Pause and Stop always work)."""
    return lambda: PROGRAM_RUNNING if programs.progress.state is RunState.RUNNING else None


def explain_in_error(motion_status: Callable[[], MotionStatus | None]) -> Callable[[str], str]:
    """A refused motion in ERROR says so: the controller's own words ("Robot does not respond") name no
    cause."""

    def explain(message: str) -> str:
        state = motion_status()
        if state in (MotionStatus.ERROR, MotionStatus.MOTION_FAILED):
            return f"The arm is in {state.value}: press Recover in the banner first (controller: {message})"
        return message

    return explain
