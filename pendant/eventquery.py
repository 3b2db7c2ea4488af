"""Searching the event log: a query, the rows it gives, and the folding of state-change runs. Shared by the
in-memory log and the SQLite store, so both answer a search the same way."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, replace

FOLDED_KIND = "state"  # runs of these become one row: a looping program must not drown the commands


@dataclass(frozen=True)
class StoredEvent:
    """One row of a search: `count` > 1 when consecutive state changes were folded into the newest one."""

    id: int
    time: float
    kind: str
    source: str
    message: str
    count: int = 1
    first_time: float | None = None  # the oldest of the folded ones


@dataclass(frozen=True)
class EventQuery:
    """Events after `since` (epoch seconds) of these kinds, whose source / message contain `who` / `text`
    (case-insensitive), newest first, at most `limit` rows (state runs folded into one when `fold`)."""

    since: float | None = None
    kinds: tuple[str, ...] = ()
    who: str = ""
    text: str = ""
    limit: int = 100
    fold: bool = False

    def matches(self, event: StoredEvent) -> bool:
        return (
            (self.since is None or event.time >= self.since)
            and (not self.kinds or event.kind in self.kinds)
            and self.who.lower() in event.source.lower()
            and self.text.lower() in event.message.lower()
        )


def fold_states(newest_first: Iterable[StoredEvent], limit: int) -> list[StoredEvent]:
    """Consecutive state changes become one row: the newest, with how many and since when."""
    out: list[StoredEvent] = []
    for event in newest_first:
        previous = out[-1] if out else None
        if previous is not None and previous.kind == FOLDED_KIND and event.kind == FOLDED_KIND:
            out[-1] = replace(previous, count=previous.count + 1, first_time=event.time)
            continue
        if len(out) == limit:
            break
        out.append(event)
    return out
