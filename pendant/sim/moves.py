"""Motion commands turned into plans: targets in joint space or in the zero point frame, from a start.

Pure functions of the arm, the planner and a `Start` snapshot read under the simulator's lock; planning
runs without the lock (see controller.py).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.controller.errors import (
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    BadRequest,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import MotionParams, MotionType, Position
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


def plan_to_configurations(
    planner: Planner, targets: list[np.ndarray], params: MotionParams, start: Start
) -> Plan:
    arm = planner.arm
    for q in targets:
        if not arm.within_limits(q):
            raise Unreachable(MSG_UNREACHABLE_POSE)
    q0, tool, radius = start.q, start.T_flange_tool, start.tool_radius
    if params.motion_type is MotionType.JOINT:
        return planner.joint(q0, targets, params, tool, radius, MSG_UNREACHABLE_POSE)
    tcp = [arm.fk(q) @ tool for q in targets]
    return planner.linear(q0, tcp, params, tool, radius, MSG_UNREACHABLE_POSE, q_final=targets[-1])


def plan_to_positions(
    planner: Planner, positions: list[Position], params: MotionParams, start: Start
) -> Plan:
    q0, tool, radius = start.q, start.T_flange_tool, start.tool_radius
    tcp_targets = [start.T_origbase_zero @ position_to_matrix(p) for p in positions]
    if params.motion_type is MotionType.LINEAR:
        return planner.linear(q0, tcp_targets, params, tool, radius, MSG_UNREACHABLE_POSITION)
    T_tool_flange = inverse(tool)
    configurations = []
    q_near = q0
    for T_tcp in tcp_targets:
        q = planner.arm.ik(T_tcp @ T_tool_flange, q_near)
        if q is None:
            raise Unreachable(MSG_UNREACHABLE_POSITION)
        configurations.append(q)
        q_near = q
    return planner.joint(q0, configurations, params, tool, radius, MSG_UNREACHABLE_POSITION)
