"""Monitoring that lasts: Prometheus metrics, the persistent event log, where the pendant keeps its data."""

from __future__ import annotations

import os
from pathlib import Path

from fastapi import FastAPI

from pendant.eventquery import EventQuery, StoredEvent
from pendant.monitoring.events_api import EVENTS_PATH, EventSource, events_router
from pendant.monitoring.eventstore import EventStore, open_event_store
from pendant.monitoring.metrics import METRICS_PATH, CommandMetrics, PendantMetrics, metrics_router
from pendant.paths import programs_dir

DATA_DIR_ENV = "PENDANT_DATA_DIR"
DATA_DIR_NAME = "pendant-data"


def data_dir(flag: str | None, programs: str | None = None) -> Path:
    """`--data DIR`, else $PENDANT_DATA_DIR, else `pendant-data/` beside the programs folder (`--programs`,
    else $PENDANT_PROGRAMS_DIR, else ./programs)."""
    if flag:
        return Path(flag)
    if os.environ.get(DATA_DIR_ENV):
        return Path(os.environ[DATA_DIR_ENV])
    folder = Path(programs) if programs else programs_dir()
    return folder.resolve().parent / DATA_DIR_NAME


def add_monitoring(app: FastAPI, metrics: PendantMetrics | None, store: EventSource | None) -> None:
    """GET /metrics and GET /pendant/events on an API app; the command counter outside everything else
    (added last), so it also counts what the token guard refuses."""
    if store is not None:
        app.include_router(events_router(store))
    if metrics is not None:
        app.include_router(metrics_router(metrics))
        app.add_middleware(CommandMetrics, metrics=metrics, served=app)


__all__ = [
    "EVENTS_PATH",
    "METRICS_PATH",
    "CommandMetrics",
    "EventQuery",
    "EventSource",
    "EventStore",
    "PendantMetrics",
    "StoredEvent",
    "add_monitoring",
    "data_dir",
    "events_router",
    "metrics_router",
    "open_event_store",
]
