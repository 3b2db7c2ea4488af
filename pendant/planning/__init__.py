"""Planning on the pendant's side: collision-free joint paths (OMPL) over the shared cell check."""

from __future__ import annotations

from pendant.planning.joint_planner import (
    MARGIN_M,
    PlannedPath,
    PlannerSettings,
    path_is_clear,
    plan_joint_path,
)

__all__ = ["MARGIN_M", "PlannedPath", "PlannerSettings", "path_is_clear", "plan_joint_path"]
