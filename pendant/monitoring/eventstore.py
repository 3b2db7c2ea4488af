"""The event log on disk: one SQLite database (WAL) that survives restarts, bounded by age and by rows.

Writes go through a queue to one writer thread, so logging an event (from the refresh loop, a stop, the API's
event loop) never waits for the disk. Reads open their own connection: WAL lets them run beside the writer.
"""

from __future__ import annotations

import logging
import queue
import sqlite3
import threading
import time
from pathlib import Path

from pendant.eventquery import FOLDED_KIND, EventQuery, StoredEvent, fold_states

log = logging.getLogger(__name__)

DB_NAME = "events.sqlite3"
MAX_AGE_S = 30 * 24 * 3600.0  # a month of history
MAX_ROWS = 500_000  # about 60 MB; the oldest go first
PRUNE_EVERY = 1000  # rows written between two prunes
QUEUE_MAX = 100_000  # events waiting for the writer; beyond that they are dropped (and counted)
MAX_LIMIT = 1000  # rows one query may return
TEXT_MAX_CHARS = 200  # a search string
BUSY_TIMEOUT_S = 5.0  # how long a write waits for a lock held by another connection
# A full disk lets some writes through (SQLite reuses the pages a prune freed), so failures come and go: the
# line that says so is written when they start, and again only this long after the last one.
PROBLEM_REPEAT_S = 60.0

_SCHEMA = """
CREATE TABLE IF NOT EXISTS events (
    id INTEGER PRIMARY KEY,
    time REAL NOT NULL,
    kind TEXT NOT NULL,
    source TEXT NOT NULL,
    message TEXT NOT NULL
);
CREATE INDEX IF NOT EXISTS events_time ON events(time);
CREATE INDEX IF NOT EXISTS events_kind ON events(kind, id);
"""


def _like(fragment: str) -> str:
    escaped = fragment[:TEXT_MAX_CHARS].replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")
    return f"%{escaped}%"


class EventStore:
    """Append from any thread with `put`; query with `search`. `close` writes what is queued and stops."""

    def __init__(self, folder: str | Path, *, max_age_s: float = MAX_AGE_S, max_rows: int = MAX_ROWS) -> None:
        self.folder = Path(folder)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.path = self.folder / DB_NAME
        self.max_age_s = max_age_s
        self.max_rows = max_rows
        self.dropped = 0  # events lost: the writer fell QUEUE_MAX behind, or the disk refused them
        self.write_problem: str | None = None  # the last write failure in words, until a write succeeds
        self.written_id = 0  # the newest event on disk: a view redraws when it moves
        self._queue: queue.Queue[tuple[int, float, str, str, str] | None] = queue.Queue(QUEUE_MAX)
        with self._connect() as db:
            db.execute("PRAGMA journal_mode=WAL")
            db.executescript(_SCHEMA)
            self.last_id: int = db.execute("SELECT COALESCE(MAX(id), 0) FROM events").fetchone()[0]
        self.written_id = self.last_id
        self._prune(self._connect())
        self._thread = threading.Thread(target=self._write_loop, name="pendant-eventstore", daemon=True)
        self._thread.start()

    def _connect(self) -> sqlite3.Connection:
        db = sqlite3.connect(self.path, timeout=BUSY_TIMEOUT_S, check_same_thread=False)
        db.execute("PRAGMA synchronous=NORMAL")  # WAL + NORMAL: durable across a crash of the process
        return db

    # --- writing --------------------------------------------------------------------------------
    def put(self, event_id: int, wall_time: float, kind: str, source: str, message: str) -> None:
        """Queue one event for the writer; never blocks."""
        try:
            self._queue.put_nowait((event_id, wall_time, kind, source, message))
        except queue.Full:
            self.dropped += 1

    def flush(self, timeout: float = 2.0) -> bool:
        """Wait until everything queued so far is on disk (tests, downloads); False on timeout."""
        deadline = time.monotonic() + timeout
        while self._queue.unfinished_tasks:
            if time.monotonic() > deadline:
                return False
            time.sleep(0.005)
        return True

    def close(self) -> None:
        if self._thread.is_alive():
            self._queue.put(None)
            self._thread.join(timeout=5.0)

    def _write_loop(self) -> None:
        db = self._connect()
        written = 0
        said_at = -PROBLEM_REPEAT_S  # monotonic time the last write failure was logged
        unsaid = False  # a run of failures began that no line has named yet
        while True:
            item = self._queue.get()
            batch = [item]
            while item is not None and len(batch) < 500:  # whatever else is waiting, in one transaction
                try:
                    item = self._queue.get_nowait()
                except queue.Empty:
                    break
                batch.append(item)
            rows = [row for row in batch if row is not None]
            try:
                with db:
                    db.executemany("INSERT OR REPLACE INTO events VALUES (?, ?, ?, ?, ?)", rows)
                written += len(rows)
                if rows:
                    self.written_id = max(self.written_id, max(row[0] for row in rows))
                if written >= PRUNE_EVERY:
                    written = 0
                    self._prune(db)
            except sqlite3.Error as error:
                self.dropped += len(rows)
                problem = f"Events could not be written to {self.path} ({error}): {self.dropped} lost so far"
                now = time.monotonic()
                unsaid = unsaid or self.write_problem is None  # a run of failures begins: said, not per batch
                if unsaid and now - said_at >= PROBLEM_REPEAT_S:
                    log.error("%s. Fix: free space on that disk or make the folder writable.", problem)
                    said_at, unsaid = now, False
                self.write_problem = problem
            else:
                self.write_problem = None
            finally:
                for _ in batch:
                    self._queue.task_done()
            if len(rows) < len(batch):  # the close() sentinel
                db.close()
                return

    def _prune(self, db: sqlite3.Connection) -> None:
        """Rotation: drop events older than max_age_s, then all but the newest max_rows."""
        with db:
            db.execute("DELETE FROM events WHERE time < ?", (time.time() - self.max_age_s,))
            db.execute("DELETE FROM events WHERE id <= (SELECT MAX(id) FROM events) - ?", (self.max_rows,))

    # --- reading --------------------------------------------------------------------------------
    def search(self, query: EventQuery, cap: int = MAX_LIMIT) -> list[StoredEvent]:
        """Newest first, at most `cap` rows whatever the query's limit (a download asks for more)."""
        limit = max(1, min(query.limit, cap))
        where: list[str] = ["1=1"]
        args: list[object] = []
        if query.since is not None:
            where.append("time >= ?")
            args.append(query.since)
        if query.kinds:
            where.append(f"kind IN ({','.join('?' * len(query.kinds))})")
            args.extend(query.kinds)
        for column, fragment in (("source", query.who), ("message", query.text)):
            if fragment:
                where.append(f"{column} LIKE ? ESCAPE '\\'")
                args.append(_like(fragment))
        condition = " AND ".join(where)
        sql = f"SELECT id, time, kind, source, message FROM events WHERE {condition} ORDER BY id DESC"
        db = self._connect()
        try:
            if not query.fold:
                return [StoredEvent(*row) for row in db.execute(f"{sql} LIMIT ?", (*args, limit))]
            return _folded(db, condition, args, limit)
        finally:
            db.close()

    def count(self) -> int:
        db = self._connect()
        try:
            return int(db.execute("SELECT COUNT(*) FROM events").fetchone()[0])
        finally:
            db.close()


def _folded(db: sqlite3.Connection, condition: str, args: list[object], limit: int) -> list[StoredEvent]:
    """Folded search without reading every state change: the page's other events through the index, then
    per gap between two of them one COUNT of the state changes there (an index range on (kind, id))."""
    columns = "id, time, kind, source, message"
    others = [
        StoredEvent(*row)
        for row in db.execute(
            f"SELECT {columns} FROM events WHERE {condition} AND kind != ? ORDER BY id DESC LIMIT ?",
            (*args, FOLDED_KIND, limit),
        )
    ]
    bounds = [None, *(event.id for event in others)]
    if len(others) < limit:
        bounds.append(0)  # the last gap reaches back to the start of the log
    out: list[StoredEvent] = []
    for i, event in enumerate([*others, None]):
        if i + 1 < len(bounds):
            upper, lower = bounds[i], bounds[i + 1]
            newest = db.execute(
                f"SELECT {columns} FROM events WHERE {condition} AND kind = ? AND id > ?"
                + (" AND id < ?" if upper is not None else "")
                + " ORDER BY id DESC LIMIT 1",
                (*args, FOLDED_KIND, lower, *([upper] if upper is not None else [])),
            ).fetchone()
            if newest is not None:
                count, first_time = db.execute(
                    f"SELECT COUNT(*), MIN(time) FROM events WHERE {condition} AND kind = ?"
                    " AND id > ? AND id <= ?",
                    (*args, FOLDED_KIND, lower, newest[0]),
                ).fetchone()
                row_id, at, kind, source, message = newest  # the five columns
                folded_from = first_time if count > 1 else None
                out.append(StoredEvent(row_id, at, kind, source, message, count, folded_from))
        if event is not None:
            out.append(event)
    return fold_states(out, limit)


def open_event_store(folder: str | Path) -> tuple[EventStore | None, str | None]:
    """The event log's store in `folder`, or (None, why) when that folder cannot hold it (read-only, full,
    not a folder): the pendant then starts with its log in memory and says so, in one line."""
    try:
        return EventStore(folder), None
    except (OSError, sqlite3.Error) as error:
        reason = getattr(error, "strerror", None) or str(error)
        return None, (
            f"The event log cannot be kept in {Path(folder).resolve()} ({reason}): it is kept in memory "
            "until the pendant stops. Fix: make that folder writable or free space on its disk, or start "
            "with --data DIR."
        )
