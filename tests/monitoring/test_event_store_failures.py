"""A disk that refuses writes now and then (full, with pages a prune freed): the pendant says so once, not
once per failing batch, and counts every event lost. A real SQLite file whose writer is refused INSERTs by
SQLite's own authorizer while the test says so."""

from __future__ import annotations

import functools
import logging
import sqlite3
from pathlib import Path

import pytest

from pendant.monitoring import eventstore
from pendant.monitoring.eventstore import EventStore
from tests.support.waiting import SAFETY_NET_S


@pytest.mark.parametrize(
    ("repeat_s", "lines"),
    [
        (3600.0, 1),  # within the repeat interval: the first run of failures is said, the next two are not
        (0.0, 3),  # past it: each run of failures is said once, not each of its three failing batches
    ],
)
def test_failures_that_come_and_go_are_said_once_a_while_and_every_lost_event_counted(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    caplog: pytest.LogCaptureFixture,
    repeat_s: float,
    lines: int,
) -> None:
    monkeypatch.setattr(eventstore, "PROBLEM_REPEAT_S", repeat_s)
    refusing = [False]
    connect = EventStore._connect

    def refused_while_told(store: EventStore) -> sqlite3.Connection:
        db = connect(store)
        db.set_authorizer(
            lambda action, *_: (
                sqlite3.SQLITE_DENY if refusing[0] and action == sqlite3.SQLITE_INSERT else sqlite3.SQLITE_OK
            )
        )
        return db

    monkeypatch.setattr(EventStore, "_connect", refused_while_told)
    # SQLite asks its authorizer when a statement is prepared: no statement cache, so every batch asks.
    monkeypatch.setattr(sqlite3, "connect", functools.partial(sqlite3.connect, cached_statements=0))
    store = EventStore(tmp_path)
    caplog.set_level(logging.ERROR, logger=eventstore.__name__)
    try:
        event_id = store.last_id
        for refused in (True, False, True, False, True):  # a disk that is full, then not, then full again
            refusing[0] = refused
            for _ in range(3):
                event_id += 1
                store.put(event_id, 0.0, "command", "test", f"event {event_id}")
                assert store.flush(timeout=SAFETY_NET_S)
            assert (store.write_problem is not None) == refused
    finally:
        refusing[0] = False
        store.close()
    said = [r.getMessage() for r in caplog.records if "could not be written" in r.getMessage()]
    assert len(said) == lines, said
    assert "Fix:" in said[0]
    assert store.dropped == 9, "three failing runs of three events each"
