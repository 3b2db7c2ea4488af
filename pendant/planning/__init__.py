"""Planning ahead of the arm: collision-free joint paths (OMPL) over the shared cell check, the digital
twin, pre-flight checks of programs and the Run gate."""

from __future__ import annotations

from pendant.planning.joint_planner import (
    MARGIN_M,
    PlannedPath,
    PlannerSettings,
    path_is_clear,
    plan_joint_path,
)

__all__ = ["MARGIN_M", "PlannedPath", "PlannerSettings", "path_is_clear", "plan_joint_path"]
