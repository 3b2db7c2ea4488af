"""Leaving a contact before planning: a start where the arm touches an obstacle (the controller took one
that touched the arm at rest, kinematics/contact.py) is planned from by first backing out of it.

OMPL needs a clear start. From a start in contact, straight joint moves are tried (towards the target first,
then each joint alone, either way, up to `ESCAPE_MAX_RAD`), each sampled `step_rad` apart under the contact
rule: never deeper into what the arm touches, never into anything new. The first one that reaches a clear
configuration (clear of the margin where it can) gives the exit; the path is then the start, the exit, and
the plan from the exit. The arm touching itself, or a link in the floor, is never a start.
"""

from __future__ import annotations

import math

import numpy as np

from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.contact import ContactGuard

ESCAPE_MAX_RAD = math.radians(30.0)  # the farthest a joint goes to leave a contact
MSG_NO_WAY_OUT = "the start touches {names}, and no straight joint move of up to {limit:g} degrees leaves it"


def _directions(q_start: np.ndarray, q_goal: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """Moves to try, each a unit direction (its leading joint turns 1 rad per unit) and how far it may go:
    towards the goal (no farther than it), then each joint alone, either way."""
    directions = []
    towards = q_goal - q_start
    distance = float(np.max(np.abs(towards)))
    if distance > 0.0:
        directions.append((towards / distance, min(ESCAPE_MAX_RAD, distance)))
    for joint in range(len(q_start)):
        for sign in (1.0, -1.0):
            unit = np.zeros(len(q_start))
            unit[joint] = sign
            directions.append((unit, ESCAPE_MAX_RAD))
    return directions


def leave_contact(
    check: CellCheck, padded: CellCheck, q_start: np.ndarray, q_goal: np.ndarray, step_rad: float
) -> np.ndarray | None:
    """A configuration clear of `check` (of `padded` where one is within reach) reached from q_start by a
    straight joint move the contact rule allows at every sample `step_rad` apart; None if none is found."""
    arm = check.arm
    for direction, reach in _directions(q_start, q_goal):
        guard = ContactGuard(check, q_start)
        first_clear = None
        for k in range(1, math.ceil(reach / step_rad) + 1):
            q = q_start + min(k * step_rad, reach) * direction
            if not arm.within_limits(q) or guard.check(q) is not None:
                break
            if not padded.collides(q):
                return q
            if first_clear is None and not check.collides(q):
                first_clear = q
        if first_clear is not None:
            return first_clear
    return None
