"""One wording for every refusal for a collision, in every tab: what the refused pose (or the way to it) would
hit, named: the obstacle, or the arm's two links, or the floor.

The controller itself says only "Collision detected" (the PULSE API's text); the page knows the cell and the
target, so it names what is in the way with the same collision checker the simulator uses.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller.errors import MSG_COLLISION
from pendant.kinematics import ArmModel
from pendant.kinematics.contact import FLOOR as CONTACT_FLOOR
from pendant.kinematics.contact import ContactGuard

FLOOR = "floor"
_SHAPE_SUFFIX = re.compile(r"_\d+$")  # the URDF's collision shapes are named link3_0, link3_1, ...


@dataclass(frozen=True)
class CollisionNamed:
    """Why a pose is refused for a collision (`reason`, None: nothing in the way) and the obstacles hit."""

    reason: str | None
    obstacles: tuple[str, ...] = ()


def quoted(names: Sequence[str]) -> str:
    return ", ".join(repr(n) for n in names)


def obstacle_words(names: Sequence[str], *, path: bool = False) -> str:
    """'Collision detected: the target touches 'Box'' (or the path to it passes through it)."""
    if not names:
        return f"{MSG_COLLISION}: the tool would touch the floor"
    if path:
        return f"{MSG_COLLISION}: the path to the target passes through {quoted(names)}"
    return f"{MSG_COLLISION}: the target touches {quoted(names)}"


def link_words(pairs: Sequence[tuple[str, str]]) -> str:
    """'Collision detected: link2 would touch link5' (the arm with itself or the floor), first pair only."""
    if not pairs:
        return MSG_COLLISION
    a, b = (_SHAPE_SUFFIX.sub("", name) for name in pairs[0])
    if a == FLOOR:
        a, b = b, a
    return f"{MSG_COLLISION}: {a} would touch {'the floor' if b == FLOOR else b}"


def name_collision(
    arm: ArmModel, q: np.ndarray, cell: CellModel | None = None, q_from: np.ndarray | None = None
) -> CollisionNamed:
    """What `q` (or the joint path from `q_from` to it) would hit, named; reason None when nothing."""
    if arm.in_collision(q):
        return CollisionNamed(link_words(arm.colliding_pairs(q)))
    if cell is None:
        return CollisionNamed(None)
    if q_from is not None:  # from where the arm is: out of a contact it may go, deeper in it may not
        return _from_where_it_is(cell, q_from, q)
    if cell.collides(q):
        hit = tuple(cell.touching(q))
        return CollisionNamed(obstacle_words(hit), hit)
    return CollisionNamed(None)


def _from_where_it_is(cell: CellModel, q_from: np.ndarray, q: np.ndarray) -> CollisionNamed:
    """The contact rule (kinematics/contact.py, as the controller checks it) at the target, then along the
    joint path to it."""
    at_target = ContactGuard(cell.check, q_from).check(q)
    worse = at_target if at_target is not None else cell.path_worse(q_from, q)
    if worse is None:
        return CollisionNamed(None)
    if worse.itself:  # on the path only: the target itself was checked first
        return CollisionNamed(f"{MSG_COLLISION}: the path to the target passes through the arm or the floor")
    if worse.obstacle is CONTACT_FLOOR:
        return CollisionNamed(obstacle_words(()))
    if worse.allowed_m is not None:
        where = f"the {'target' if at_target is not None else 'path to the target'} {worse.describe()}"
        return CollisionNamed(f"{MSG_COLLISION}: {where}", (worse.obstacle,))
    return CollisionNamed(obstacle_words((worse.obstacle,), path=at_target is None), (worse.obstacle,))


def is_unnamed_collision(message: str) -> bool:
    """The controller's bare "Collision detected" (nothing after it to say what is in the way)."""
    return message.strip().startswith(MSG_COLLISION) and ":" not in message


def explain_collision(
    message: str,
    arm: ArmModel,
    q: np.ndarray | None,
    cell: CellModel | None = None,
    q_from: np.ndarray | None = None,
) -> CollisionNamed:
    """A controller's refusal in the shared words: a bare "Collision detected" for the pose `q` gets what
    is in the way named; a collision the controller named already keeps its words, with the obstacles the
    page finds (to draw them red); any other message is kept as it is."""
    if q is None or not message.strip().startswith(MSG_COLLISION):
        return CollisionNamed(message)
    named = name_collision(arm, q, cell, q_from)
    if not is_unnamed_collision(message):
        return CollisionNamed(message, named.obstacles)
    if named.reason is None:  # the controller saw one the page's model does not (finer sampling)
        return CollisionNamed(f"{MSG_COLLISION} on the way to the target")
    return named
