"""One consistent reading of the controller, taken off the UI thread and shown by every panel."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Protocol, runtime_checkable

import numpy as np

from pendant.controller import Controller, ControllerError, MotionStatus, Position, SignalLevel
from pendant.controller.errors import ControllerOffline, Emergency
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS


@runtime_checkable
class ReportsGripper(Protocol):
    """A controller that knows its gripper's opening (the simulator), or what it last told the gripper (the
    remote client: the PULSE API has no such read); None when it cannot tell."""

    def gripper_opening(self) -> float | None: ...


@dataclass(frozen=True)
class Snapshot:
    taken_at: float
    q: np.ndarray | None = None  # radians
    position: Position | None = None
    motion_status: MotionStatus | None = None
    tool_name: str = ""
    robot_id: str = ""
    outputs: dict[int, SignalLevel] = field(default_factory=dict)
    inputs: dict[int, SignalLevel] = field(default_factory=dict)
    gripper_opening: float | None = None  # 0 closed .. 1 open; None: unknown
    error: str | None = None  # the controller's message when the last reading failed
    latency_s: float | None = None
    online: bool = False  # the controller answered (an emergency 503 or a 500 is an answer too)
    last_known: LastKnown | None = None  # when q is None (a fault): the last reading that had it


@dataclass(frozen=True)
class LastKnown:
    """The arm's last known joints and TCP, shown greyed while the controller cannot say (EMERGENCY)."""

    q: np.ndarray
    position: Position | None
    taken_at: float


def carry_last_known(previous: Snapshot, current: Snapshot) -> Snapshot:
    """`current`, remembering where the arm last was when it cannot read it now (q stays None: nothing
    takes a last known pose for a live one but the status readout)."""
    if current.q is not None:
        return current
    if previous.q is not None:
        return replace(current, last_known=LastKnown(previous.q, previous.position, previous.taken_at))
    return replace(current, last_known=previous.last_known)


def read_snapshot(controller: Controller, *, with_io: bool, robot_id: str, tool_name: str) -> Snapshot:
    """Read pose, position and status (and IO when `with_io`); a controller error becomes `error`."""
    started = time.monotonic()
    try:
        pose = controller.get_pose()
        position = controller.get_position()
        status = controller.get_motion_status()
        outputs = {p: controller.get_output(p) for p in OUTPUT_PORTS} if with_io else {}
        inputs = {p: controller.get_input(p) for p in INPUT_PORTS} if with_io else {}
    except ControllerError as error:
        # In an emergency the controller refuses every call with 503: that is its state, not a lost link.
        return Snapshot(
            taken_at=started,
            motion_status=MotionStatus.EMERGENCY if isinstance(error, Emergency) else None,
            error=error.message,
            robot_id=robot_id,
            tool_name=tool_name,
            online=not isinstance(error, ControllerOffline),
            latency_s=time.monotonic() - started,
        )
    opening = controller.gripper_opening() if isinstance(controller, ReportsGripper) else None
    return Snapshot(
        taken_at=started,
        q=np.radians(np.asarray(pose.angles, dtype=float)),
        position=position,
        motion_status=status,
        tool_name=tool_name,
        robot_id=robot_id,
        outputs=outputs,
        inputs=inputs,
        gripper_opening=opening,
        latency_s=time.monotonic() - started,
        online=True,
    )


def format_position(position: Position) -> str:
    p, r = position.point, position.rotation
    xyz = " ".join(f"{v * 1000:8.1f}" for v in (p.x, p.y, p.z))
    rpy = " ".join(f"{math.degrees(v):7.1f}" for v in (r.roll, r.pitch, r.yaw))
    return f"XYZ mm {xyz} | RPY deg {rpy}"
