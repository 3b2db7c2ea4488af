"""Motion commands turned into plans: targets in joint space or in the zero point frame, from a start.

Pure functions of the arm, the planner and a `Start` snapshot read under the simulator's lock; planning
runs without the lock (see controller.py).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from pendant.controller.errors import (
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    BadRequest,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.system_types import RobotAction
from pendant.controller.types import InterpolationType, MotionParams, MotionType, Pose, Position
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.transforms import inverse, position_to_matrix
from pendant.sim.planner import Plan, Planner

# A run is planned in one go before it is accepted (100 LINEAR waypoints 15 cm apart take most of a second),
# and a queue longer than anyone can follow is a runaway client, not a program: both are capped.
MAX_WAYPOINTS = 100


def check_waypoint_count(count: int) -> None:
    if count == 0:
        raise BadRequest()
    if count > MAX_WAYPOINTS:
        raise PreconditionFailed(f"waypoints must be 1 to {MAX_WAYPOINTS} per run (got {count})")


@dataclass(frozen=True)
class Start:
    """What a plan is made from, read under the lock: where the queue ends, the tool and the zero point."""

    q: np.ndarray
    tool_radius: float
    T_flange_tool: np.ndarray
    T_origbase_zero: np.ndarray
    freezes: int  # freezes so far: one more by the time the plan is made means "cancelled"
    cell: CellCheck | None = None  # obstacles and the tool's shape


@dataclass(frozen=True)
class Step:
    """One planned motion to queue, with the waypoint actions due along it (seconds after its start)."""

    plan: Plan
    actions: tuple[tuple[float, RobotAction], ...] = ()


def blends_of(waypoints: Sequence[Pose] | Sequence[Position], scale: float = 1.0) -> list[float] | None:
    """Each waypoint's `blend` (SDK >= 1.7) times `scale`, or None when no waypoint has one."""
    blends = [float(getattr(w, "blend", 0.0)) * scale for w in waypoints]
    return blends if any(blends) else None


def actions_of(waypoints: Sequence[Pose] | Sequence[Position]) -> list[list[RobotAction]]:
    return [list(getattr(w, "actions", None) or []) for w in waypoints]


def _timed(plan: Plan, actions: list[list[RobotAction]]) -> tuple[tuple[float, RobotAction], ...]:
    items: list[tuple[float, RobotAction]] = []
    for s, due in zip(plan.waypoint_s, actions, strict=False):
        t = plan.time_at(s)
        items.extend((t, action) for action in due)
    return tuple(sorted(items, key=lambda item: item[0]))


def plan_run(
    plan_one: Callable[[list[int], Start], Plan],
    count: int,
    params: MotionParams,
    start: Start,
    actions: list[list[RobotAction]],
) -> list[Step]:
    """One motion through all `count` targets, or (RAW) one stop-at-target motion per target.

    `plan_one(indices, start)` plans through the targets with those indices from `start`."""
    if params.interpolation is not InterpolationType.RAW or count == 1:
        plan = plan_one(list(range(count)), start)
        return [Step(plan, _timed(plan, actions))]
    steps = []
    for k in range(count):
        plan = plan_one([k], start)
        steps.append(Step(plan, _timed(plan, [actions[k]])))
        start = replace(start, q=plan.q_end)
    return steps


def plan_to_configurations(
    planner: Planner,
    targets: list[np.ndarray],
    params: MotionParams,
    start: Start,
    blends: list[float] | None = None,
) -> Plan:
    """`blends`: per target, radians of joint travel (JOINT) or metres of TCP travel (LINEAR)."""
    arm = planner.arm
    for q in targets:
        if not arm.within_limits(q):
            raise Unreachable(MSG_UNREACHABLE_POSE)
    q0, tool, radius, cell = start.q, start.T_flange_tool, start.tool_radius, start.cell
    if params.motion_type is MotionType.JOINT:
        return planner.joint(q0, targets, params, tool, radius, MSG_UNREACHABLE_POSE, cell, blends)
    tcp = [arm.fk(q) @ tool for q in targets]
    return planner.linear(
        q0, tcp, params, tool, radius, MSG_UNREACHABLE_POSE, q_final=targets[-1], cell=cell, blends_m=blends
    )


def plan_to_positions(
    planner: Planner,
    positions: list[Position],
    params: MotionParams,
    start: Start,
    blends: list[float] | None = None,
) -> Plan:
    """`blends`: per target, metres of TCP travel (LINEAR) or radians of joint travel (JOINT)."""
    q0, tool, radius, cell = start.q, start.T_flange_tool, start.tool_radius, start.cell
    tcp_targets = [start.T_origbase_zero @ position_to_matrix(p) for p in positions]
    if params.motion_type is MotionType.LINEAR:
        return planner.linear(
            q0, tcp_targets, params, tool, radius, MSG_UNREACHABLE_POSITION, cell=cell, blends_m=blends
        )
    T_tool_flange = inverse(tool)
    configurations = []
    q_near = q0
    for T_tcp in tcp_targets:
        q = planner.arm.ik(T_tcp @ T_tool_flange, q_near)
        if q is None:
            raise Unreachable(MSG_UNREACHABLE_POSITION)
        configurations.append(q)
        q_near = q
    return planner.joint(q0, configurations, params, tool, radius, MSG_UNREACHABLE_POSITION, cell, blends)
