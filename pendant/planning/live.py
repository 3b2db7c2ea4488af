"""A plan against a controller as it is now: its cell, tool and zero point read, then the start and target
checked and the path searched. POST /pendant/plan, the page's Plan around and a program's planned Move J
all plan through here, so they refuse in the same words ("the target itself is inside 'fixture'").
"""

from __future__ import annotations

import numpy as np

from pendant.controller import Controller
from pendant.controller.types import Pose, Position
from pendant.kinematics import ArmModel
from pendant.planning.joint_planner import DEFAULT_BUDGET_S, Cancelled, PlannedPath, plan_joint_path
from pendant.planning.request import Cell, PlanTarget, cell_of, checked_angles, target_angles


def read_cell(controller: Controller) -> Cell:
    """The controller's obstacles, tool shape, tool and zero point (GETs only)."""
    return Cell(
        controller.get_obstacles(), controller.get_tool_shape(), controller.get_tool(), controller.get_base()
    )


def plan_on(
    controller: Controller,
    arm: ArmModel,
    target: PlanTarget,
    *,
    start_deg: list[float] | None = None,
    budget_s: float = DEFAULT_BUDGET_S,
    cancelled: Cancelled | None = None,
) -> PlannedPath:
    """A collision-free joint path to `target` from `start_deg` (default: where the arm is), in the
    controller's cell as it is now. ControllerError (412 kinds) saying why not."""
    cell = read_cell(controller)
    check = cell_of(arm, cell)
    start = start_deg if start_deg is not None else controller.get_pose().angles
    q_start = checked_angles(arm, check, start, "start")
    q_goal = target_angles(arm, check, cell, target, q_start)
    return plan_joint_path(check, q_start, q_goal, budget_s=budget_s, cancelled=cancelled)


def as_poses(path: PlannedPath) -> list[Pose]:
    """The path's waypoints after its start, in degrees: what a run takes from where the arm is
    (pendant.program.blended.run_planned_path)."""
    return [Pose(angles=[float(a) for a in np.degrees(q)]) for q in path.waypoints[1:]]


class ControllerPlanner:
    """The planner a program runner is given (pendant.program.motion.PathPlanner): waypoints from where
    the arm is to `goal`, in the cell as it is when the step runs."""

    def __init__(self, arm: ArmModel, budget_s: float = DEFAULT_BUDGET_S) -> None:
        self.arm = arm
        self.budget_s = budget_s

    def __call__(self, controller: Controller, goal: Pose | Position, cancelled: Cancelled) -> list[Pose]:
        target = PlanTarget(angles=list(goal.angles)) if isinstance(goal, Pose) else PlanTarget(position=goal)
        path = plan_on(controller, self.arm, target, budget_s=self.budget_s, cancelled=cancelled)
        return as_poses(path)
