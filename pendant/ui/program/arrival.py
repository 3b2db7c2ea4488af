"""A move's "At arrival" choice: the dropdown's options, and the waypoint action each one stands for."""

from __future__ import annotations

from pendant.controller import SignalLevel
from pendant.controller.types import OUTPUT_PORTS
from pendant.program import GripperAction, GripperAtWaypoint, OutputAction
from pendant.program.models import WaypointAction

NO_ACTION = "nothing"
ARRIVAL_OPTIONS = (
    NO_ACTION,
    *(f"DO{p} {level.value}" for p in OUTPUT_PORTS for level in SignalLevel),
    "gripper open",
    "gripper close",
)


def arrival_option(action: WaypointAction | None) -> str:
    """The option that shows `action` (a move's first)."""
    if isinstance(action, OutputAction):
        return f"DO{action.port} {action.value.value}"
    if isinstance(action, GripperAtWaypoint):
        return f"gripper {action.value.value}"
    return NO_ACTION


def arrival_actions(option: str) -> tuple[WaypointAction, ...]:
    """The actions a move does at arrival for the chosen `option`."""
    if option == NO_ACTION:
        return ()
    if option.startswith("gripper "):
        return (GripperAtWaypoint(value=GripperAction(option.split()[1])),)
    port, level = option.split()
    return (OutputAction(port=int(port[2:]), value=SignalLevel(level)),)
