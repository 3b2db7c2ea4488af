"""`GET /pendant/events?since=&kind=&who=&text=&limit=&fold=`: the persistent event log as JSON, newest first.

Served on the API port in both modes, under /pendant/ (never forwarded to the controller). A read: open to
anyone, like every GET. Bad parameters get 412 with a message naming them, as the PULSE API answers.
"""

from __future__ import annotations

import datetime as dt
import json
from dataclasses import asdict
from typing import Annotated, Protocol

from fastapi import APIRouter, Query
from starlette.responses import Response

from pendant.eventlog import EventKind
from pendant.eventquery import EventQuery, StoredEvent
from pendant.monitoring.eventstore import MAX_LIMIT, TEXT_MAX_CHARS

EVENTS_PATH = "/pendant/events"
DEFAULT_LIMIT = 100
KIND_NAMES = tuple(kind.value for kind in EventKind)


def parse_since(text: str | None) -> float | None:
    """Epoch seconds (`1763800000.5`) or an ISO 8601 time (`2026-11-22T10:00:00Z`; no zone means UTC)."""
    if text is None or text == "":
        return None
    try:
        return float(text)
    except ValueError:
        pass
    try:
        when = dt.datetime.fromisoformat(text)
    except ValueError:
        raise ValueError(f"since must be epoch seconds or an ISO 8601 time (got {text[:40]!r})") from None
    if when.tzinfo is None:
        when = when.replace(tzinfo=dt.UTC)
    return when.timestamp()


def parse_kinds(values: list[str]) -> tuple[str, ...]:
    """`kind=error&kind=refused` or `kind=error,refused`; each one of KIND_NAMES."""
    kinds = tuple(part.strip() for value in values for part in value.split(",") if part.strip())
    unknown = [kind for kind in kinds if kind not in KIND_NAMES]
    if unknown:
        raise ValueError(f"kind must be one of {', '.join(KIND_NAMES)} (got {unknown[0][:20]!r})")
    return tuple(dict.fromkeys(kinds))  # each once: at most five, however often the query repeats them


def event_json(event: StoredEvent) -> dict[str, object]:
    row = asdict(event)
    row["iso_time"] = dt.datetime.fromtimestamp(row["time"], dt.UTC).isoformat()
    return row


def _bounded(name: str, value: str) -> str:
    if len(value) > TEXT_MAX_CHARS:
        raise ValueError(f"{name} must be at most {TEXT_MAX_CHARS} characters (got {len(value)})")
    return value


def _limit(text: str) -> int:
    try:
        limit = int(text)
    except ValueError:
        limit = 0
    if not 1 <= limit <= MAX_LIMIT:
        raise ValueError(f"limit must be an integer between 1 and {MAX_LIMIT} (got {text[:20]!r})")
    return limit


def _refusal(message: str) -> Response:
    return Response(json.dumps(message), status_code=412, media_type="text/plain")


class EventSource(Protocol):
    """Where the events come from: the log (on disk or, when its folder cannot hold it, in memory) or its
    store."""

    def search(self, query: EventQuery, cap: int = ...) -> list[StoredEvent]: ...
    def flush(self, timeout: float = ...) -> bool: ...


def events_router(store: EventSource) -> APIRouter:
    router = APIRouter(tags=["pendant"])

    # A plain `def`: SQLite runs in FastAPI's thread pool, never on the event loop.
    @router.get(EVENTS_PATH, summary="The pendant's event log (persistent), newest first")
    def get_events(
        since: str | None = None,
        kind: Annotated[list[str], Query()] = [],  # noqa: B006 (FastAPI copies it)
        who: str = "",
        text: str = "",
        limit: str = str(DEFAULT_LIMIT),
        fold: str = "false",
    ) -> Response:
        try:
            query = EventQuery(
                parse_since(since),
                parse_kinds(kind),
                _bounded("who", who),
                _bounded("text", text),
                _limit(limit),
                fold.lower() in ("1", "true", "yes"),
            )
        except ValueError as exc:
            return _refusal(str(exc))
        store.flush(timeout=0.5)  # what was logged before the request is in the answer
        rows = [event_json(event) for event in store.search(query)]
        return Response(json.dumps({"events": rows}), media_type="application/json")

    return router
