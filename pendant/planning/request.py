"""A plan request as a script sends it (POST /pendant/plan): the body, and its start and target as joint
angles checked against the limits and the cell before any planning."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Annotated

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.errors import PreconditionFailed, Unreachable
from pendant.controller.types import Position, Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.analytic_ik import ik_branches, nearest_equivalents
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.cell_shapes import cell_check
from pendant.kinematics.limits import N_JOINTS
from pendant.kinematics.transforms import inverse, position_to_matrix
from pendant.planning.joint_planner import DEFAULT_BUDGET_S, MAX_BUDGET_S

MSG_OUTSIDE_LIMITS = (
    "the {what} is outside the joint limits (joint {joint}: {angle:g} degrees, limits {low:g} to {high:g})"
)
MSG_START_INSIDE = "the start itself is {inside}"
MSG_TARGET_INSIDE = "the target itself is {inside}"
MSG_NO_CLEAR_BRANCH = "the target position is reachable only with the arm or its tool {inside}"
# Strict: "60" and true are not angles (a script sending them has a bug to hear about); 60 is 60.0.
Degrees = Annotated[float, Field(strict=True, allow_inf_nan=False)]


class Angles(BaseModel):
    """Six joint angles in degrees, base first (as PULSE poses)."""

    model_config = ConfigDict(extra="forbid")
    angles: Annotated[list[Degrees], Field(min_length=N_JOINTS, max_length=N_JOINTS)]


class PlanTarget(BaseModel):
    """Where to go: joint angles, or a TCP position (the controller's zero point frame, its current tool)."""

    model_config = ConfigDict(extra="forbid")
    angles: Annotated[list[Degrees], Field(min_length=N_JOINTS, max_length=N_JOINTS)] | None = None
    position: Position | None = None

    @model_validator(mode="after")
    def _one_of(self) -> PlanTarget:
        if (self.angles is None) == (self.position is None):
            raise ValueError("target needs exactly one of angles and position")
        return self


class PlanRequest(BaseModel):
    """POST /pendant/plan's body."""

    model_config = ConfigDict(extra="forbid", populate_by_name=True)
    target: PlanTarget
    start: Angles | None = Field(default=None, alias="from")
    budget_s: Annotated[float, Field(strict=True, gt=0.0, le=MAX_BUDGET_S, allow_inf_nan=False)] = (
        DEFAULT_BUDGET_S
    )


@dataclass(frozen=True)
class Cell:
    """What the controller holds, as the planner needs it."""

    obstacles: list[Obstacle]
    tool_shape: ToolShape
    tool: Tool
    base: Position


def _inside(check: CellCheck, q: np.ndarray) -> str | None:
    """'inside 'fixture'' (the obstacles touched), 'in the floor or in itself', or None when clear."""
    touching = check.touching(q)
    if touching is None:
        return None
    if touching:
        return "inside " + ", ".join(repr(name) for name in touching)
    return "touching the floor or itself"


def checked_angles(arm: ArmModel, check: CellCheck, degrees: list[float], what: str) -> np.ndarray:
    """Angles in radians, or PreconditionFailed: outside the limits, or in collision (saying with what).
    A start may touch obstacles (or the tool the floor): the contact rule lets the path leave them; never
    the arm itself or a link in the floor."""
    q = np.radians(np.array(degrees, dtype=float))
    for joint, (angle, low, high) in enumerate(zip(q, arm.lower, arm.upper, strict=True), start=1):
        if not low <= angle <= high:
            raise Unreachable(
                MSG_OUTSIDE_LIMITS.format(
                    what=what,
                    joint=joint,
                    angle=math.degrees(angle),
                    low=math.degrees(low),
                    high=math.degrees(high),
                )
            )
    if what == "start" and not check.touch(q).itself:
        return q
    inside = _inside(check, q)
    if inside is not None:
        raise PreconditionFailed(
            (MSG_START_INSIDE if what == "start" else MSG_TARGET_INSIDE).format(inside=inside)
        )
    return q


def target_angles(
    arm: ArmModel, check: CellCheck, cell: Cell, target: PlanTarget, q_start: np.ndarray
) -> np.ndarray:
    """The target in radians: its angles as given (a +-2 pi joint goes where it says, not a turn nearer),
    or, for a position, the clear IK branch nearest the start (each joint's equivalent nearest it)."""
    if target.angles is not None:
        return checked_angles(arm, check, target.angles, "target")
    assert target.position is not None
    T_base_tcp = position_to_matrix(cell.base) @ position_to_matrix(target.position)
    T_base_flange = T_base_tcp @ inverse(position_to_matrix(cell.tool.position))
    raw = ik_branches(arm.table, T_base_flange, float(q_start[5]))
    if not raw:
        raise Unreachable()
    candidates, in_limits = nearest_equivalents(np.array(raw), q_start, arm.lower, arm.upper)
    candidates = candidates[in_limits]
    if len(candidates) == 0:
        raise Unreachable()
    order = np.argsort(np.sum((candidates - q_start) ** 2, axis=1))
    first_inside = None
    for q in candidates[order]:
        if not np.allclose(arm.fk(q), T_base_flange, atol=1e-6):
            continue
        inside = _inside(check, q)
        if inside is None:
            return q
        first_inside = first_inside or inside
    if first_inside is None:
        raise Unreachable()
    raise PreconditionFailed(MSG_NO_CLEAR_BRANCH.format(inside=first_inside))


def cell_of(arm: ArmModel, cell: Cell) -> CellCheck:
    return cell_check(arm, cell.obstacles, cell.tool_shape, cell.tool)
