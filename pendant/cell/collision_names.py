"""What a refused pose (or the way to it) would hit, found with the simulator's own checker and said in the
shared words (kinematics/collision_words.py): the Target, Go to, Run and Cell checks and the banner use it.

The controller itself says only "Collision detected" (the PULSE API's text); the pendant knows the cell and
the target, so it names what is in the way with the same collision checker the simulator uses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller.errors import MSG_COLLISION
from pendant.kinematics import ArmModel
from pendant.kinematics.collision_words import contact_words, is_unnamed_collision, link_words, obstacle_words
from pendant.kinematics.contact import FLOOR as CONTACT_FLOOR
from pendant.kinematics.contact import ContactGuard


@dataclass(frozen=True)
class CollisionNamed:
    """Why a pose is refused for a collision (`reason`, None: nothing in the way) and the obstacles hit."""

    reason: str | None
    obstacles: tuple[str, ...] = ()


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
    hit = () if worse.itself or worse.obstacle is CONTACT_FLOOR else (str(worse.obstacle),)
    return CollisionNamed(contact_words(worse, path=at_target is None), hit)


def explain_collision(
    message: str,
    arm: ArmModel,
    q: np.ndarray | None,
    cell: CellModel | None = None,
    q_from: np.ndarray | None = None,
) -> CollisionNamed:
    """A controller's refusal in the shared words: a bare "Collision detected" for the pose `q` gets what
    is in the way named; a collision the controller named already keeps its words, with the obstacles the
    pendant finds (to draw them red); any other message is kept as it is."""
    if q is None or not message.strip().startswith(MSG_COLLISION):
        return CollisionNamed(message)
    named = name_collision(arm, q, cell, q_from)
    if not is_unnamed_collision(message):
        return CollisionNamed(message, named.obstacles)
    if named.reason is None:  # the controller saw one the page's model does not (finer sampling)
        return CollisionNamed(f"{MSG_COLLISION} on the way to the target")
    return named
