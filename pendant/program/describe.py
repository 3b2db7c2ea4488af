"""One line per step, as the operator reads it in the step list: "Move J to P1 @ 20%", "Loop 3 times"."""

from __future__ import annotations

from pendant.controller.types import MotionType
from pendant.program.models import (
    DEFAULT_PALLET_NAME,
    CallStep,
    CommentStep,
    GripperAtWaypoint,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    Offset,
    OutputAction,
    OutputStep,
    PalletStep,
    PathStep,
    Step,
    WaitInputStep,
    WaitStep,
    WaypointAction,
)


def _offset(offset: Offset) -> str:
    parts = [
        f"{axis}{value:+g}" for axis, value in (("x", offset.x), ("y", offset.y), ("z", offset.z)) if value
    ]
    parts += [
        f"{axis}{value:+g}°"
        for axis, value in (("rx", offset.rx), ("ry", offset.ry), ("rz", offset.rz))
        if value
    ]
    return f" {' '.join(parts) or '+0'} mm ({offset.frame.value})"


def _action(action: WaypointAction) -> str:
    if isinstance(action, OutputAction):
        return f"DO{action.port} {action.value.value}"
    assert isinstance(action, GripperAtWaypoint)
    return f"gripper {action.value.value}"


def describe_step(step: Step) -> str:
    match step:
        case MoveStep():
            letter = "J" if step.motion is MotionType.JOINT else "L"
            text = f"Move {letter} to {step.waypoint}"
            if step.offset is not None:
                text += _offset(step.offset)
            text += f" @ {step.speed:g}%"
            if step.planned:
                text += ", planned around obstacles"
            if step.blend_mm:
                text += f", blend {step.blend_mm:g} mm"
            if step.actions:
                text += ", then " + ", ".join(_action(a) for a in step.actions)
            return text
        case GripperStep():
            return f"Gripper {step.action.value} ({step.timeout_ms} ms)"
        case OutputStep():
            return f"Set DO{step.port} {step.level.value}"
        case WaitInputStep():
            return f"Wait DI{step.port} {step.level.value} (timeout {step.timeout_ms} ms)"
        case WaitStep():
            return f"Wait {step.ms} ms"
        case CommentStep():
            return f"# {step.text}"
        case LoopStep():
            if step.mode is LoopMode.TIMES:
                return f"Loop {step.times} times"
            return f"Loop {step.mode.value} DI{step.port} {step.level.value}"
        case IfStep():
            return f"If DI{step.port} {step.level.value}"
        case CallStep():
            return f"Call {step.program}"
        case PalletStep():
            grid = f"{step.rows}x{step.columns}" + (f"x{step.layers}" if step.layers > 1 else "")
            name = "" if step.name == DEFAULT_PALLET_NAME else f" {step.name}"
            corners = ", ".join(step.corners)
            return f"Pallet{name} {grid} from {corners} (approach {step.approach_mm:g} mm)"
        case PathStep():
            return (
                f"Path {step.name}: {len(step.points)} waypoints, {step.tol_mm:g} mm / {step.tol_deg:g}° "
                f"@ {step.velocity_mm_s:g} mm/s"
            )
    raise TypeError(f"not a step: {step!r}")
