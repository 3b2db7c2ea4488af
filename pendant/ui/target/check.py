"""Is a dragged target executable? IK to the branch nearest the current pose, then limits and collision:
with itself and the floor, and with the cell's obstacles at the target and along the joint path to it (under
the contact rule, kinematics/contact.py, as the controller checks it)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.kinematics import ArmModel
from pendant.kinematics.contact import FLOOR, ContactGuard


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
        return _check_from(cell, q_from, q)
    if cell.collides(q):
        hit = cell.touching(q)
        where = f"the target touches {_names(hit)}" if hit else "the tool would touch the floor"
        return TargetCheck(q, f"{MSG_COLLISION}: {where}", tuple(hit))
    return TargetCheck(q)


def _check_from(cell: CellModel, q_from: np.ndarray, q: np.ndarray) -> TargetCheck:
    """The contact rule at the target (against where the arm is), then along the path to it."""
    at_target = ContactGuard(cell.check, q_from).check(q)
    worse = at_target if at_target is not None else cell.path_worse(q_from, q)
    if worse is None:
        return TargetCheck(q)
    if worse.itself:  # on the path only: the target itself was checked first
        return TargetCheck(q, f"{MSG_COLLISION}: the path to the target passes through the arm or the floor")
    if worse.obstacle is FLOOR:
        return TargetCheck(q, f"{MSG_COLLISION}: the tool would touch the floor")
    if worse.allowed_m is not None:
        where = f"the {'target' if at_target is not None else 'path to the target'} {worse.describe()}"
    elif at_target is not None:
        where = f"the target touches {worse.obstacle!r}"
    else:
        where = f"the path to the target passes through {worse.obstacle!r}"
    return TargetCheck(q, f"{MSG_COLLISION}: {where}", (worse.obstacle,))
