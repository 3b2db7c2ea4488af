"""The step the Program tab's Add buttons make: a default of each kind, placed where the selection says."""

from __future__ import annotations

from pendant.controller import SignalLevel
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS
from pendant.program import (
    CallStep,
    CommentStep,
    EditError,
    GripperAction,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    Offset,
    OutputStep,
    PalletStep,
    ProgramWorkspace,
    Step,
    WaitInputStep,
    WaitStep,
)
from pendant.program.models import DEFAULT_INPUT_TIMEOUT_MS
from pendant.program.tree import Line

ADD_OPTIONS = ("Gripper open", "Gripper close", "Set DO", "Wait DI", "Wait", "Comment")
STRUCTURE_OPTIONS = ("Loop", "If DI", "Pallet", "Call", "Move to waypoint", "Relative move")
DEFAULT_WAIT_MS = 500


def new_step(option: str, shared: ProgramWorkspace, waypoint: str | None) -> Step:
    """The step `option` (one of ADD_OPTIONS or STRUCTURE_OPTIONS) adds; a move goes to `waypoint`.

    Raises EditError when the program lacks what the step needs (a waypoint, three corners, another program).
    """
    match option:
        case "Gripper open" | "Gripper close":
            return GripperStep(action=GripperAction.OPEN if option == "Gripper open" else GripperAction.CLOSE)
        case "Set DO":
            return OutputStep(port=OUTPUT_PORTS[0], level=SignalLevel.HIGH)
        case "Wait DI":
            return WaitInputStep(
                port=INPUT_PORTS[0], level=SignalLevel.HIGH, timeout_ms=DEFAULT_INPUT_TIMEOUT_MS
            )
        case "Wait":
            return WaitStep(ms=DEFAULT_WAIT_MS)
        case "Comment":
            return CommentStep(text="")
        case "Loop":
            return LoopStep(mode=LoopMode.TIMES, times=2)
        case "If DI":
            return IfStep(port=INPUT_PORTS[0], level=SignalLevel.HIGH)
        case "Call":
            names = [n for n in shared.saved_programs() if n != shared.file_name]
            if not names:
                raise EditError("Call runs a saved program: save another program first")
            return CallStep(program=names[0])
        case "Pallet":
            names = shared.program.waypoint_names()
            if len(names) < 3:
                raise EditError("A pallet needs three taught corners: teach three waypoints first")
            return PalletStep(corners=(names[-3], names[-2], names[-1]))
        case "Move to waypoint" | "Relative move":
            if waypoint is None:
                raise EditError("Teach a waypoint first (Record, or Waypoints > Add waypoint here)")
            offset = Offset(z=50.0) if option == "Relative move" else None
            return MoveStep(waypoint=waypoint, offset=offset)
    raise EditError(f"Unknown step {option!r}")


def waypoint_here(line: Line | None, chosen: str | None) -> str | None:
    """The waypoint a new move goes to: the selected move's, else the one `chosen` in the table."""
    if line is not None and isinstance(line.step, MoveStep):
        return line.step.waypoint
    return chosen
