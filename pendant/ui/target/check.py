"""Is a dragged target executable? IK to the branch nearest the current pose, then limits and collision:
with itself and the floor, and with the cell's obstacles at the target and along the joint path to it (under
the contact rule, kinematics/contact.py, as the controller checks it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.cell.collision_names import name_collision
from pendant.cell.geometry import CellModel
from pendant.controller.errors import MSG_UNREACHABLE_POSITION
from pendant.kinematics import ArmModel


@dataclass(frozen=True)
class TargetCheck:
    q: np.ndarray | None  # the joint angles that reach the target (radians), when reachable
    reason: str | None = None  # why it cannot be executed, in the controller's words
    touching: tuple[str, ...] = ()  # the obstacles the target, or the path to it, would hit

    @property
    def ok(self) -> bool:
        return self.reason is None


def check_flange_target(
    arm: ArmModel,
    T_base_flange: np.ndarray,
    q_near: np.ndarray,
    cell: CellModel | None = None,
    q_from: np.ndarray | None = None,
) -> TargetCheck:
    q = arm.ik(T_base_flange, q_near)
    if q is None:
        return TargetCheck(None, MSG_UNREACHABLE_POSITION)
    return check_joint_target(arm, q, cell, q_from)


def check_joint_target(
    arm: ArmModel, q: np.ndarray, cell: CellModel | None = None, q_from: np.ndarray | None = None
) -> TargetCheck:
    """`cell`: the controller's obstacles and tool shape; `q_from`: where the arm is, to check the path."""
    if not arm.within_limits(q):
        return TargetCheck(q, "Unreachable Pose")
    named = name_collision(arm, q, cell, q_from)  # the words every tab uses (kinematics/collision_words.py)
    return TargetCheck(q, named.reason, named.obstacles)
