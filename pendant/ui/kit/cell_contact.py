"""An obstacle touching the arm where it stands: the Cell tab's line saying so, and the event log's entries.

A controller takes such an obstacle (see kinematics/contact.py): the arm may back out of it, not go deeper.
The 3D scene draws it red (cell_scene.py); this tells the operator in words, and the log keeps when it began
and ended.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from pendant.eventlog import EventKind, EventLog
from pendant.kinematics.contact import Contact

ArmContacts = tuple[tuple[str, tuple[str, ...]], ...]  # (obstacle name, the links touching it), in order
EVENT_SOURCE = "cell"


def arm_contacts(contacts: Mapping[str | None, Contact]) -> ArmContacts:
    """The obstacles (not the floor) in `contacts`, with their links, as the page keeps them."""
    return tuple((name, contact.links) for name, contact in contacts.items() if name is not None)


def _links(links: Sequence[str]) -> str:
    return ", ".join(links)


def contact_line(contacts: ArmContacts) -> str:
    """The Cell tab's line: empty when the arm touches nothing."""
    if not contacts:
        return ""
    which = "; ".join(f"'{name}' ({_links(links)})" for name, links in contacts)
    return (
        f"**The arm touches {which}** (drawn red): it may move out of the contact, "
        "not deeper in; a motion that would touch another obstacle is refused."
    )


class ContactLog:
    """Logs each obstacle that starts or stops touching the arm (once, not at every reading)."""

    def __init__(self, events: EventLog) -> None:
        self._events = events
        self._touching: dict[str, tuple[str, ...]] = {}
        self._known: set[str] | None = None  # the obstacles of the last reading (None: no reading yet)

    def note(self, obstacles: Sequence[str], contacts: ArmContacts) -> None:
        """One reading of the cell: the obstacles' names and which of them touch the arm."""
        now = dict(contacts)
        for name, links in now.items():
            if name in self._touching:
                continue
            if self._known is not None and name not in self._known:
                message = f"Obstacle '{name}' added touching the arm ({_links(links)})"
            else:
                message = f"The arm touches obstacle '{name}' ({_links(links)})"
            self._events.record(EventKind.STATE, EVENT_SOURCE, message)
        for name in self._touching:
            if name not in now and name in obstacles:
                self._events.record(EventKind.STATE, EVENT_SOURCE, f"The arm is clear of obstacle '{name}'")
        self._touching = now
        self._known = set(obstacles)
