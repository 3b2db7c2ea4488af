"""Is a dragged target executable? IK to the branch nearest the current pose, then limits and collision."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.kinematics import ArmModel


@dataclass(frozen=True)
class TargetCheck:
    q: np.ndarray | None  # the joint angles that reach the target (radians), when reachable
    reason: str | None = None  # why it cannot be executed, in the controller's words

    @property
    def ok(self) -> bool:
        return self.reason is None


def check_flange_target(arm: ArmModel, T_base_flange: np.ndarray, q_near: np.ndarray) -> TargetCheck:
    q = arm.ik(T_base_flange, q_near)
    if q is None:
        return TargetCheck(None, MSG_UNREACHABLE_POSITION)
    return check_joint_target(arm, q)


def check_joint_target(arm: ArmModel, q: np.ndarray) -> TargetCheck:
    if not arm.within_limits(q):
        return TargetCheck(q, "Unreachable Pose")
    if arm.in_collision(q):
        return TargetCheck(q, MSG_COLLISION)
    return TargetCheck(q)
