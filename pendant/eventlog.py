"""The pendant's event log: state changes, errors and every command with who sent it, newest last.

One log per pendant process, shared by the web UI and the API server (threads and the event loop both write
to it), kept in memory as a bounded ring and, with an EventStore, on disk (SQLite: it survives restarts and
is what the dashboard searches). Recording never waits for the disk.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum
from typing import Protocol

from pendant.eventquery import EventQuery, StoredEvent, fold_states

log = logging.getLogger(__name__)

DEFAULT_CAPACITY = 1000


class EventKind(StrEnum):
    STATE = "state"  # the controller's motion state changed
    ERROR = "error"  # the controller reported an error, or a command failed
    COMMAND = "command"  # a command was accepted (from a browser or an API client)
    REFUSED = "refused"  # a command or a control request was refused (viewer, wrong token)
    CONTROL = "control"  # who is the operator changed


@dataclass(frozen=True)
class Event:
    seq: int  # 1, 2, 3, ... in the order they were logged
    wall_time: float  # time.time()
    kind: EventKind
    source: str  # who: "browser #3 (10.0.0.7)", "API 10.0.0.9 (python-requests/2.31)", "controller"
    message: str


class EventStore(Protocol):
    """Where the log keeps its events on disk (monitoring.eventstore's SQLite store is the one there is)."""

    last_id: int  # the newest event stored when the log opened it: numbers go on from there
    written_id: int  # the newest event on disk
    dropped: int  # events that never reached the disk
    write_problem: str | None  # the last write failure in words, until a write succeeds

    def put(self, event_id: int, wall_time: float, kind: str, source: str, message: str) -> None: ...

    def search(self, query: EventQuery, cap: int = ...) -> list[StoredEvent]: ...

    def flush(self, timeout: float = ...) -> bool:
        """Wait until what was put is on disk (True) or `timeout` s passed (False)."""
        ...


class EventLog:
    """A thread-safe ring of the last `capacity` events; `seq` tells readers whether anything is new."""

    def __init__(
        self,
        capacity: int = DEFAULT_CAPACITY,
        now: Callable[[], float] = time.time,
        store: EventStore | None = None,
        storage_problem: str | None = None,
    ) -> None:
        self._events: deque[Event] = deque(maxlen=capacity)
        self.storage_problem = storage_problem  # why the log is in memory only (None: on disk, or meant so)
        self._lock = threading.Lock()
        self._now = now
        self.store = store
        self._seq = store.last_id if store is not None else 0  # numbers go on across restarts
        self._listeners: list[Callable[[Event], None]] = []

    def on_record(self, listener: Callable[[Event], None]) -> None:
        """Call `listener(event)` after each event is logged (metrics count them); it must be quick."""
        self._listeners.append(listener)

    @property
    def seq(self) -> int:
        """The number of the last event logged (0 when none): unchanged means nothing new."""
        return self._seq

    def record(self, kind: EventKind, source: str, message: str) -> Event:
        with self._lock:
            self._seq += 1
            event = Event(self._seq, self._now(), kind, source, message)
            self._events.append(event)
            if self.store is not None:
                self.store.put(event.seq, event.wall_time, event.kind.value, source, message)
        for listener in self._listeners:
            listener(event)
        level = logging.WARNING if kind in (EventKind.ERROR, EventKind.REFUSED) else logging.INFO
        log.log(level, "%s %s: %s", kind.value, source, message)
        return event

    def recent(self, count: int | None = None) -> list[Event]:
        """The last `count` events (all kept when None), oldest first."""
        with self._lock:
            events = list(self._events)
        return events if count is None else events[-count:]

    @property
    def dropped(self) -> int:
        """Events that never reached the disk (the writer fell behind, or the disk refused them)."""
        return self.store.dropped if self.store is not None else 0

    @property
    def problem(self) -> str | None:
        """What the Dashboard says about the log's storage: kept in memory only, or failing to write."""
        if self.store is not None:
            return self.store.write_problem
        return self.storage_problem

    @property
    def searchable_seq(self) -> int:
        """The newest event a search can find (on disk, with a store): a view redraws when it moves."""
        return self.store.written_id if self.store is not None else self._seq

    def flush(self, timeout: float = 2.0) -> bool:
        """Wait until what was logged is searchable (on disk, with a store)."""
        return self.store.flush(timeout) if self.store is not None else True

    def search(self, query: EventQuery, cap: int | None = None) -> list[StoredEvent]:
        """Newest first: the store's whole history, or the ring kept in memory without one."""
        if self.store is not None:
            return self.store.search(query) if cap is None else self.store.search(query, cap)
        rows = (
            StoredEvent(e.seq, e.wall_time, e.kind.value, e.source, e.message)
            for e in reversed(self.recent())
        )
        matching = (row for row in rows if query.matches(row))
        limit = query.limit if cap is None else min(query.limit, cap)
        if query.fold:
            return fold_states(matching, limit)
        return [row for _, row in zip(range(limit), matching, strict=False)]
