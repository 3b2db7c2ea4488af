"""The persistent event log: what a real pendant logged is found again after a restart (even a kill), the
search filters and folds, the API bounds its answers, rotation bounds the file, and logging never waits."""

from __future__ import annotations

import os
import signal
import sqlite3
import subprocess
import time
from pathlib import Path
from typing import Any

import httpx
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient

from pendant.eventlog import EventKind, EventLog
from pendant.monitoring import EventQuery, EventStore, events_router
from pendant.monitoring.events_api import parse_since
from pendant.monitoring.eventstore import BUSY_TIMEOUT_S, DB_NAME
from tests.support.launchers import running_pendant
from tests.support.waiting import SAFETY_NET_S, wait_until

POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}


def events(base: str, **params: str | int | float) -> list[dict[str, Any]]:  # the API's JSON
    answer = httpx.get(f"{base}/pendant/events", params=params, timeout=SAFETY_NET_S)
    assert answer.status_code == 200, answer.text
    return answer.json()["events"]


def test_events_survive_a_restart_and_a_kill(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path)) as base:
        assert httpx.put(f"{base}/pose?speed=20", json=POSE, timeout=SAFETY_NET_S).status_code == 200
        assert (
            httpx.put(f"{base}/pose?speed=20", json={"angles": [1]}, timeout=SAFETY_NET_S).status_code == 400
        )
        before = events(base, kind="command,error")  # the API's commands (the arm's states are logged too)
    assert [e["message"] for e in before] == ["PUT /pose -> 400", "PUT /pose -> 200"]
    assert before[0]["kind"] == "error" and str(before[0]["source"]).startswith("API 127.0.0.1")

    with running_pendant("--data", str(tmp_path)) as base:
        quit_line, *again = events(base, kind="command,error")
        assert again == before, "the same events, ids and times after a restart"
        assert quit_line["source"] == "pendant" and str(quit_line["message"]).startswith("Quitting (SIGTERM)")
        assert httpx.put(f"{base}/signal/output/1/high", timeout=SAFETY_NET_S).status_code == 200
        newest = events(base, limit=1, kind="command")[0]
        assert newest["message"] == "PUT /signal/output/1/high -> 200"
        assert newest["id"] > int(before[0]["id"]), "numbering goes on"
        os.kill(_pid_on(base), signal.SIGKILL)  # no clean shutdown: what the page showed must still be there
    with running_pendant("--data", str(tmp_path)) as base:
        assert [e["message"] for e in events(base, kind="command")] == [
            "PUT /signal/output/1/high -> 200",  # no "Quitting" after it: killed with -9, it said nothing
            str(quit_line["message"]),
            "PUT /pose -> 200",
        ]


def _pid_on(base: str) -> int:
    """The pid of the pendant serving `base` (the test started it; found by its listening port)."""
    port = base.rsplit(":", 1)[1]
    out = subprocess.run(["ss", "-Hltnp", f"sport = :{port}"], capture_output=True, text=True).stdout
    return int(out.split("pid=")[1].split(",")[0])


def test_api_filters_folds_and_bounds(tmp_path: Path) -> None:
    store = EventStore(tmp_path)
    log = EventLog(store=store)
    log.record(EventKind.COMMAND, "browser #1 (10.0.0.7)", "Run program pick")
    for i in range(1200):  # a looping program
        log.record(EventKind.STATE, "controller", "IDLE → RUNNING" if i % 2 == 0 else "RUNNING → IDLE")
    log.record(EventKind.ERROR, "program", "Step 3 (Move J to Far @ 50%) failed: Unreachable Pose")
    log.record(EventKind.REFUSED, "browser #2 (10.0.0.9)", "Move J: you are a viewer")
    store.flush()

    folded = store.search(EventQuery(fold=True, limit=10))
    assert [(e.kind, e.count) for e in folded] == [
        ("refused", 1),
        ("error", 1),
        ("state", 1200),
        ("command", 1),
    ]
    assert folded[2].message == "RUNNING → IDLE" and folded[2].first_time is not None
    assert [e.message for e in store.search(EventQuery(kinds=("command", "error"), limit=5))] == [
        "Step 3 (Move J to Far @ 50%) failed: Unreachable Pose",
        "Run program pick",
    ]
    assert [e.source for e in store.search(EventQuery(who="10.0.0.9"))] == ["browser #2 (10.0.0.9)"]
    assert len(store.search(EventQuery(text="50%"))) == 1, "% is a character, not a wildcard"
    assert store.search(EventQuery(text="unreachable pose"))[0].kind == "error", "case-insensitive"
    assert len(store.search(EventQuery(limit=100_000))) == 1000, "a query returns at most 1,000 rows"
    store.close()


@pytest.mark.parametrize(
    ("params", "message"),
    [
        ({"limit": 0}, "limit must be an integer between 1 and 1000"),
        ({"limit": "many"}, "limit must be an integer between 1 and 1000"),
        ({"kind": "gossip"}, "kind must be one of state, error, command, refused, control"),
        ({"since": "yesterday"}, "since must be epoch seconds or an ISO 8601 time"),
        ({"text": "x" * 201}, "text must be at most 200 characters"),
    ],
)
def test_bad_parameters_get_412_naming_them(tmp_path: Path, params: dict[str, object], message: str) -> None:
    store = EventStore(tmp_path)
    app = FastAPI()
    app.include_router(events_router(store))
    answer = TestClient(app).get("/pendant/events", params=params)
    store.close()
    assert answer.status_code == 412
    assert message in answer.json()


def test_since_accepts_iso_and_epoch(tmp_path: Path) -> None:
    now = [1_800_000_000.0]
    store = EventStore(tmp_path)
    log = EventLog(now=lambda: now[0], store=store)
    log.record(EventKind.COMMAND, "a", "old")
    now[0] += 3600
    log.record(EventKind.COMMAND, "a", "new")
    store.flush()
    for since in (str(now[0] - 60), "2027-01-15T09:00:00+00:00"):
        assert [e.message for e in store.search(EventQuery(since=parse_since(since)))] == ["new"]
    store.close()


def test_rotation_by_rows_and_age(tmp_path: Path) -> None:
    store = EventStore(tmp_path, max_rows=100)
    log = EventLog(store=store, now=lambda: time.time() - 40 * 24 * 3600)  # older than the 30 days kept
    for i in range(50):
        log.record(EventKind.COMMAND, "old", f"#{i}")
    store.flush()
    log = EventLog(store=store)
    for i in range(1200):  # past a prune
        log.record(EventKind.COMMAND, "new", f"#{i}")
    store.flush()
    store.close()
    reopened = EventStore(tmp_path, max_rows=100)
    kept = reopened.search(EventQuery(limit=1000))
    reopened.close()
    assert len(kept) == 100
    assert {e.source for e in kept} == {"new"} and kept[0].message == "#1199"


def test_logging_never_waits_for_the_disk(tmp_path: Path) -> None:
    """Another process holds the database locked for writing: recording still returns at once, and the
    events reach the disk once the lock is gone."""
    store = EventStore(tmp_path)
    log = EventLog(store=store)
    blocker = sqlite3.connect(tmp_path / DB_NAME)
    blocker.execute("BEGIN EXCLUSIVE")
    started = time.perf_counter()
    for i in range(1000):
        log.record(EventKind.STATE, "controller", f"#{i}")
    elapsed = time.perf_counter() - started
    blocker.rollback()
    blocker.close()
    assert store.flush(timeout=SAFETY_NET_S)
    assert store.count() == 1000
    store.close()
    # A single write waiting for the lock would have taken the whole busy timeout.
    assert elapsed < BUSY_TIMEOUT_S, f"recording waited {elapsed:.3f} s for the disk"


def test_the_store_folds_and_filters_as_the_memory_log_does(tmp_path: Path) -> None:
    """The store's folded search (index counts per gap) agrees with folding every row one by one."""
    import random

    rng = random.Random(7)
    store = EventStore(tmp_path)
    stamp = time.time()  # one time for both logs (and recent: rotation drops what is older than 30 days)
    on_disk, in_memory = EventLog(store=store, now=lambda: stamp), EventLog(capacity=5000, now=lambda: stamp)
    kinds = [EventKind.STATE] * 6 + [EventKind.COMMAND, EventKind.ERROR, EventKind.REFUSED, EventKind.CONTROL]
    for i in range(3000):
        kind, who = rng.choice(kinds), rng.choice(["controller", "browser #1", "API 10.0.0.9"])
        for log in (on_disk, in_memory):
            log.record(kind, who, f"{kind.value} #{i}")
    store.flush()
    for query in (
        EventQuery(fold=True, limit=40),
        EventQuery(fold=True, limit=1000),
        EventQuery(fold=True, kinds=("state", "error"), limit=50),
        EventQuery(fold=True, kinds=("state",), limit=5),
        EventQuery(fold=True, who="browser", limit=60),
        EventQuery(fold=True, text="#1", limit=60),
    ):
        assert on_disk.search(query) == in_memory.search(query), query
    store.close()


def test_without_the_page_state_changes_are_logged_too(tmp_path: Path) -> None:
    with running_pendant("--data", str(tmp_path)) as base:  # --no-ui
        wait_until(lambda: any(e["message"] == "offline → IDLE" for e in events(base)), what="IDLE logged")
        assert httpx.put(f"{base}/sim/fault/error", timeout=SAFETY_NET_S).status_code == 200
        wait_until(lambda: events(base, limit=1)[0]["message"] == "IDLE → ERROR", what="ERROR logged")
        newest = events(base, limit=1)[0]
        assert newest["kind"] == "error" and newest["source"] == "controller"
