"""What a recording writes besides the motors, from what the page last read: the TCP, IO and motion status,
the cell's obstacles (/cell) and the program step running (/program, as the Program tab numbers and words
it)."""

from __future__ import annotations

from pendant.program import ProgramWorkspace, describe_step
from pendant.program.runner import RunState
from pendant.telemetry import ArmState
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.snapshot import Snapshot


def program_step(programs: ProgramWorkspace) -> tuple[int, str, str] | None:
    """(line 1-based, the step's text, the run state); line 0 and no text between steps (finished, stopped);
    None before anything ran."""
    progress = programs.progress
    if progress.state is RunState.IDLE:
        return None
    index = progress.step_index if progress.step_index is not None else progress.failed_step
    lines = programs.lines()
    if index is None or not 0 <= index < len(lines):
        return (0, "", progress.state.value)
    return (index + 1, describe_step(lines[index].step), progress.state.value)


def arm_state(snapshot: Snapshot, cell: CellState, programs: ProgramWorkspace) -> ArmState:
    status = snapshot.motion_status.value if snapshot.motion_status is not None else None
    return ArmState(
        snapshot.position,
        snapshot.outputs,
        snapshot.inputs,
        status,
        obstacles=cell.obstacles,
        program=program_step(programs),
    )
