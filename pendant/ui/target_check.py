"""Is a dragged target executable? IK to the branch nearest the current pose, then limits and collision:
with itself and the floor, and with the cell's obstacles at the target and along the joint path to it (under
the contact rule, kinematics/contact.py, as the controller checks it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
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


def _names(names: list[str]) -> str:
    return ", ".join(repr(n) for n in names)


def check_joint_target(
    arm: ArmModel, q: np.ndarray, cell: CellModel | None = None, q_from: np.ndarray | None = None
) -> TargetCheck:
    """`cell`: the controller's obstacles and tool shape; `q_from`: where the arm is, to check the path."""
    if not arm.within_limits(q):
        return TargetCheck(q, "Unreachable Pose")
    if arm.in_collision(q):
        return TargetCheck(q, MSG_COLLISION)
    if cell is None:
        return TargetCheck(q)
    if q_from is not None:  # from where the arm is: out of a contact it may go, deeper in it may not
        worse = cell.path_worse(q_from, q)
        if worse is None:
            return TargetCheck(q)
        if worse.obstacle is None:
            return TargetCheck(q, f"{MSG_COLLISION}: the tool would touch the floor")
        name = worse.obstacle
        if worse.allowed_m is not None:
            where = f"the path to the target {worse.describe()}"
        elif name in cell.touching(q):
            where = f"the target touches {name!r}"
        else:
            where = f"the path to the target passes through {name!r}"
        return TargetCheck(q, f"{MSG_COLLISION}: {where}", (name,))
    if cell.collides(q):
        hit = cell.touching(q)
        where = f"the target touches {_names(hit)}" if hit else "the tool would touch the floor"
        return TargetCheck(q, f"{MSG_COLLISION}: {where}", tuple(hit))
    return TargetCheck(q)
