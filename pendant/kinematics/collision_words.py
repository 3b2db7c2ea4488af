"""One wording for every refusal for a collision, wherever it is said (the simulator, the jog, every tab of
the page): what the refused pose (or the way to it) would hit, named: the obstacle, the arm's two links, or
the floor. "Collision detected" (the PULSE API's own text) first, so a client matching it still matches.

Words only: the checks that find what is hit live with the arm model and the cell; this module sits low in
the layers (kinematics) so the jog, the simulator and the page all say the same thing for the same collision.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from pendant.controller.errors import MSG_COLLISION
from pendant.kinematics.contact import FLOOR as CONTACT_FLOOR
from pendant.kinematics.contact import Worse

FLOOR = "floor"  # the arm model's name of the floor in its colliding pairs
_SHAPE_SUFFIX = re.compile(r"_\d+$")  # the URDF's collision shapes are named link3_0, link3_1, ...
PATH = "the path to the target"


def collision(what: str) -> str:
    """'Collision detected: <what>'."""
    return f"{MSG_COLLISION}: {what}"


def quoted(names: Sequence[str]) -> str:
    return ", ".join(repr(n) for n in names)


def obstacle_words(names: Sequence[str], *, path: bool = False) -> str:
    """'Collision detected: the arm would touch 'Box'' (or the path to the target passes through it); no
    name: the tool in the floor."""
    if not names:
        return collision("the tool would touch the floor")
    if path:
        return collision(f"{PATH} passes through {quoted(names)}")
    return collision(f"the arm would touch {quoted(names)}")


def link_words(pairs: Sequence[tuple[str, str]]) -> str:
    """'Collision detected: link2 would touch link5' (the arm with itself or the floor), first pair only."""
    if not pairs:
        return MSG_COLLISION
    a, b = (_SHAPE_SUFFIX.sub("", name) for name in pairs[0])
    if a == FLOOR:
        a, b = b, a
    return collision(f"{a} would touch {'the floor' if b == FLOOR else b}")


def pose_words(pairs: Sequence[tuple[str, str]], obstacles: Sequence[str]) -> str:
    """What a pose in collision would hit: the arm's own links (or a link in the floor) when they touch
    (`pairs`, the arm model's colliding pairs), else the obstacles, else the tool in the floor."""
    return link_words(pairs) if pairs else obstacle_words(obstacles)


def contact_words(worse: Worse, *, path: bool = False) -> str:
    """The contact rule's refusal (kinematics/contact.py) in the same words: at the target, or on the
    path to it (`path`)."""
    if worse.itself:
        where = PATH + " passes through" if path else "the arm would touch"
        return collision(f"{where} the arm or the floor")
    if worse.obstacle is CONTACT_FLOOR:
        return obstacle_words(())
    if worse.allowed_m is not None:  # deeper into one it already touched
        return collision(f"{PATH if path else 'the arm'} {worse.describe()}")
    return obstacle_words((worse.obstacle,), path=path)


def is_unnamed_collision(message: str) -> bool:
    """The controller's bare "Collision detected" (nothing after it to say what is in the way)."""
    return message.strip().startswith(MSG_COLLISION) and ":" not in message
