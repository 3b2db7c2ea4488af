"""The contact rule: an arm already touching an obstacle may move, as long as it does not go deeper.

A controller takes an obstacle that touches the arm where it stands (its own SDK's README adds one), so the
arm can be in contact when a motion starts. Refusing every motion from there would trap it; allowing every
motion would drive it through. The rule, applied sample by sample along a motion's path:

- touching an obstacle that was not touched at the previous sample (a NEW contact) is refused;
- an obstacle touched all along may be touched no deeper than the shallowest the path has been in it so far,
  plus `CONTACT_DEEPER_TOLERANCE_M` (samples are a few millimetres apart; the depth is not exact);
- leaving an obstacle ends its allowance: touching it again later in the same motion is a new contact.

So a motion that backs out of a contact is allowed and one that pushes in is refused at its first sample.
The arm touching itself, or one of its links in the floor, is never allowed (only the tool may be in the
floor under the rule, as in an obstacle). The rule sits on the one cell check (kinematics/cell_check.py):
its yes/no test first, and the depths (its signed distances) only at a sample where something touches.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Protocol

import numpy as np

# How much deeper than its shallowest so far a contact may get between two samples before it counts as
# pushing in: above the depth query's noise and the path's sampling (a few mm of TCP travel), well below
# anything an operator would call "deeper".
CONTACT_DEEPER_TOLERANCE_M = 0.001
FLOOR = None  # the key of the floor (the tool's shape under z = 0) among the touched obstacles' names


@dataclass(frozen=True)
class Contact:
    """One obstacle touching the arm: how deep (metres, 0 for a graze) and which links touch it."""

    depth_m: float
    links: tuple[str, ...]


Contacts = Mapping[str | None, Contact]  # obstacle name (FLOOR: the floor) -> its contact


@dataclass(frozen=True)
class Touch:
    """What touches at one configuration: `itself` (the arm with itself, or a link in the floor: never
    allowed) and the contacts the rule weighs."""

    itself: bool
    contacts: Contacts


class ContactQuery(Protocol):
    """What the rule needs of a collision checker."""

    def collides(self, q: np.ndarray) -> bool:
        """Anything touches the arm or its tool at q (the fast yes/no)."""
        ...

    def touch(self, q: np.ndarray) -> Touch:
        """What touches at q: the arm itself, and every obstacle with its depth and links."""
        ...


@dataclass(frozen=True)
class Worse:
    """Why a sample is refused: `obstacle` (FLOOR: the floor) is newly touched (`allowed_m` None) or is
    `depth_m` deep where the path allows `allowed_m`."""

    obstacle: str | None
    depth_m: float
    allowed_m: float | None
    itself: bool = False  # the arm would touch itself or put a link in the floor (`obstacle` unused)

    def describe(self) -> str:
        if self.itself:
            return "would touch itself or the floor"
        what = "the floor" if self.obstacle is FLOOR else repr(self.obstacle)
        if self.allowed_m is None:
            return f"would touch {what}"
        return f"would go deeper into {what} ({self.allowed_m * 1000:.0f} mm -> {self.depth_m * 1000:.0f} mm)"


def worse_contact(
    allowed: Mapping[str | None, float],
    depths: Mapping[str | None, float],
    tolerance: float = CONTACT_DEEPER_TOLERANCE_M,
) -> Worse | None:
    """The first contact in `depths` that is new or deeper than `allowed` (+ tolerance); None if none."""
    for name, depth in depths.items():
        if name not in allowed:
            return Worse(name, depth, None)
        if depth > allowed[name] + tolerance:
            return Worse(name, depth, allowed[name])
    return None


class ContactGuard:
    """Follows one motion from `q_start`, sample by sample in path order (see the module's rule)."""

    def __init__(self, query: ContactQuery, q_start: np.ndarray) -> None:
        self._query = query
        self.start = dict(query.touch(q_start).contacts) if query.collides(q_start) else {}
        self._allowed = {name: contact.depth_m for name, contact in self.start.items()}

    def check(self, q: np.ndarray, collides: bool | None = None) -> Worse | None:
        """None if the path may go on to q (and q becomes the reference for the next sample). `collides`:
        the yes/no answer at q when the caller has it already (from a batch check)."""
        if not (self._query.collides(q) if collides is None else collides):  # the common case: no depth
            self._allowed = {}
            return None
        touch = self._query.touch(q)
        if touch.itself:
            return Worse(None, 0.0, None, itself=True)
        depths = {name: contact.depth_m for name, contact in touch.contacts.items()}
        worse = worse_contact(self._allowed, depths)
        if worse is None:
            self._allowed = {name: min(depth, self._allowed[name]) for name, depth in depths.items()}
        return worse
