"""`GET /metrics`: the pendant and its arm in the Prometheus text format (prometheus_client), both modes.

Counters are kept by the pendant as things happen (commands by endpoint and status, refusals, motion
failures, events, program runs); the arm's readings are read from the controller at scrape time
(controller_metrics.py). A read like any GET: open without the access token.

Every counter series exists at 0 from the start: each API command (each changing route by its template,
each answer status), each page command (by its name, each outcome: once a page is served), each event kind,
each motion failure source. Prometheus' rate() and increase() need a sample before the first event, or a
fresh site's first command and first refusal of each kind would never show. Labels are route templates
(`DELETE /environment/{obstacle}`) and command names (`Delete obstacle`), never raw paths or the names in a
page's label, so the number of series is fixed at start.
"""

from __future__ import annotations

import re
import time
from collections.abc import Iterable

from fastapi import APIRouter, FastAPI
from prometheus_client import (
    CONTENT_TYPE_LATEST,
    CollectorRegistry,
    Counter,
    Gauge,
    Info,
    disable_created_metrics,
    generate_latest,
)
from prometheus_client.core import CounterMetricFamily, GaugeMetricFamily, Metric
from prometheus_client.registry import Collector
from starlette.responses import Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from pendant import __version__
from pendant.access.token import changes_robot
from pendant.controller.operations import OPERATIONS, find_operation
from pendant.controller.protocol import Controller
from pendant.eventlog import Event, EventKind, EventLog
from pendant.monitoring.controller_metrics import ControllerCollector

METRICS_PATH = "/metrics"
OTHER = "other"  # a command to no route of the pendant (answered 404 or 405), or of no known page name
# Every status the pendant answers a command with (the PULSE API's, the access guard's, the proxy's).
ACCEPTED_STATUSES = ("200",)
REFUSAL_STATUSES = tuple(
    str(status) for status in (400, 401, 403, 404, 405, 409, 412, 413, 415, 422, 429, 431, 500, 502, 503, 504)
)
MOTION_ENDPOINTS = frozenset({"/pose", "/position", "/poses/run", "/positions/run", "/pack"})
MOTION_FAILURE_STATUSES = frozenset(
    {412, 500, 502, 503}
)  # the arm cannot (not: a malformed or unauthorised request)
# Every source of a motion failure, counted from 0 at start: Prometheus' increase() needs a first sample
# before the first failure, or a fresh pendant's first failures would not count towards an alert.
MOTION_FAILURE_SOURCES = ("api", "page", "program", "controller")
# The page's commands by name: its label up to what names a thing (`Delete obstacle 'box-7'`, `DO3 HIGH`,
# `Retry step 7 (banner)`, `Program: Run 'pick'`). The longest name a label starts with (a whole word) is
# its series; a label of none is counted as OTHER.
PAGE_COMMANDS = (
    *("Freeze", "Protective stop", "Stop", "Pause", "Recover", "Home", "Relax", "Pack"),
    *("Move J", "Move L", "Move (planned)", "Move by hand", "Plan around", "Open gripper", "Close gripper"),
    *("DO", "DI", "Bind stop", "Unbind stop", "Free drive on", "Free drive off"),
    *("Set tool", "Set tool shape", "Set base", "Inject", "Reset", "Reset simulator"),
    *("Add obstacle", "Update obstacle", "Delete obstacle", "Delete all obstacles"),
    *("Save cell", "Apply cell"),
    *("Program", "Record path", "Stop recording", "Recorded path"),
    *("Retry step", "Skip step", "Resume program", "Stop program", "Leave free drive", "Finish untwisting"),
)
PAGE_STATUSES = ("sent", "failed", "refused")  # ActivityLog's outcomes; the last two are refusals
_BY_LENGTH = sorted(PAGE_COMMANDS, key=len, reverse=True)


def page_command(label: str) -> str:
    """The name a page label is counted under: the longest of PAGE_COMMANDS it starts with as a whole word
    (`DO3 HIGH` -> `DO`), else OTHER."""
    for name in _BY_LENGTH:
        if label.startswith(name) and (len(label) == len(name) or not label[len(name)].isalpha()):
            return name
    return OTHER


class _EventLogHealth(Collector):
    """Whether the event log reaches the disk: events lost on the way, and whether it is kept there at all."""

    def __init__(self, events: EventLog) -> None:
        self._events = events

    def collect(self) -> Iterable[Metric]:
        yield CounterMetricFamily(
            "pendant_events_dropped",
            "Events of the log that never reached the disk",
            value=self._events.dropped,
        )
        yield GaugeMetricFamily(
            "pendant_event_log_on_disk",
            "1 when the event log is kept on disk, 0 when only in memory (its folder could not hold it)",
            value=0.0 if self._events.store is None else 1.0,
        )


class PendantMetrics:
    """The pendant's Prometheus registry. `viewers` is set by the page (browsers connected)."""

    def __init__(self, controller: Controller, *, mode: str, model: str, robot_url: str | None) -> None:
        # No `*_created` sample beside each counter: it would double a scrape made of ~1,400 series at 0,
        # and Prometheus' rate() does not read it.
        disable_created_metrics()
        self.registry = CollectorRegistry()
        r = self.registry
        Info("pendant", "The pendant serving this arm", registry=r).info(
            {"version": __version__, "mode": mode, "model": model, "robot_url": robot_url or ""}
        )
        started = time.monotonic()
        Gauge("pendant_uptime_seconds", "Seconds since the pendant started", registry=r).set_function(
            lambda: time.monotonic() - started
        )
        self.commands = Counter(
            "pendant_commands",
            "Commands (PUT/POST and page buttons) by answer",
            ["source", "endpoint", "status"],
            registry=r,
        )
        self.refusals = Counter(
            "pendant_command_refusals",
            "Commands refused or failed (HTTP status >= 400, page refusals)",
            ["source", "endpoint", "status"],
            registry=r,
        )
        self.motion_failures = Counter(
            "pendant_motion_failures",
            "Motion commands refused by the controller, program runs failed, the arm going to an alarm state",
            ["source"],
            registry=r,
        )
        for source in MOTION_FAILURE_SOURCES:
            self.motion_failures.labels(source)
        self.events = Counter("pendant_events", "Events logged, by kind", ["kind"], registry=r)
        for kind in EventKind:
            self.events.labels(kind.value)
        self.program_runs = Counter("pendant_program_runs", "Program runs started", registry=r)
        self.program_failures = Counter("pendant_program_failures", "Program runs that failed", registry=r)
        self.viewers = Gauge("pendant_viewers_connected", "Browsers showing the page", registry=r)
        self.registry.register(ControllerCollector(controller))

    def start_at_zero(self, endpoints: Iterable[str], source: str = "api") -> None:
        """Create every (endpoint, status) series of `source` at 0, refusals too."""
        for endpoint in endpoints:
            for status in ACCEPTED_STATUSES:
                self.commands.labels(source, endpoint, status)
            for status in REFUSAL_STATUSES:
                self.commands.labels(source, endpoint, status)
                self.refusals.labels(source, endpoint, status)

    def start_page_at_zero(self) -> None:
        """Create every page command series (each name of PAGE_COMMANDS and OTHER, each outcome) at 0: a page
        is served."""
        for name in (*PAGE_COMMANDS, OTHER):
            for status in PAGE_STATUSES:
                self.commands.labels("page", name, status)
                if status != "sent":
                    self.refusals.labels("page", name, status)

    def count_command(self, source: str, endpoint: str, status: str, *, failed: bool, motion: bool) -> None:
        """Count a command; `endpoint` is a route template (API) or a page label (counted by its name)."""
        if source != "api":
            endpoint = page_command(endpoint)
        self.commands.labels(source, endpoint, status).inc()
        if failed:
            self.refusals.labels(source, endpoint, status).inc()
            if motion:
                self.motion_failures.labels(source).inc()

    def watch(self, events: EventLog) -> None:
        """Count every event logged, by kind."""

        def counted(event: Event) -> None:
            self.events.labels(event.kind.value).inc()

        events.on_record(counted)
        self.registry.register(_EventLogHealth(events))

    def exposition(self) -> bytes:
        return generate_latest(self.registry)


Template = tuple[str, str, re.Pattern[str]]  # method, route template, its regex


def command_templates(app: FastAPI) -> list[Template]:
    """The app's own routes that change something, from its OpenAPI paths (FastAPI's public view of its
    routes, included routers flattened); the PULSE operations are named by the operations table."""
    found: list[Template] = []
    for path, item in app.openapi().get("paths", {}).items():
        regex = re.compile(re.sub(r"\\\{[^}]+\\\}", "[^/]+", re.escape(path)) + "/?")
        found += [(method.upper(), path, regex) for method in item if changes_robot(method.upper())]
    return found


def route_label(method: str, path: str, templates: Iterable[Template]) -> str:
    """`METHOD template` of the operation or route `path` asks for, else OTHER: never the raw path."""
    operation = find_operation(method, path)
    if operation is not None:
        return f"{operation.method} {operation.path}"
    for verb, template, regex in templates:
        if verb == method and regex.fullmatch(path):
            return f"{verb} {template}"
    return OTHER


def command_endpoints(templates: Iterable[Template]) -> list[str]:
    """Every label a command can take: the table's changing operations, the app's routes, OTHER."""
    labels = [f"{op.method} {op.path}" for op in OPERATIONS if changes_robot(op.method)]
    labels += [f"{method} {template}" for method, template, _ in templates]
    return [*dict.fromkeys([*labels, OTHER])]


class CommandMetrics:
    """ASGI middleware (outermost): counts every PUT/POST/DELETE by route template and the status it was
    answered with. Built by Starlette at the first request, once every route is included: its series are
    created then, before the first scrape answers."""

    def __init__(self, app: ASGIApp, metrics: PendantMetrics, served: FastAPI) -> None:
        self.app = app
        self.metrics = metrics
        self.templates = command_templates(served)
        metrics.start_at_zero(command_endpoints(self.templates))

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or not changes_robot(scope["method"]):
            await self.app(scope, receive, send)
            return
        path: str = scope["path"]
        label = route_label(scope["method"], path, self.templates)

        async def send_and_count(message: Message) -> None:
            if message["type"] == "http.response.start":
                status = int(message["status"])
                self.metrics.count_command(
                    "api",
                    label,
                    str(status),
                    failed=status >= 400,
                    motion=path in MOTION_ENDPOINTS and status in MOTION_FAILURE_STATUSES,
                )
            await send(message)

        await self.app(scope, receive, send_and_count)


def metrics_router(metrics: PendantMetrics) -> APIRouter:
    router = APIRouter(tags=["pendant"])

    # A plain `def`: the scrape reads the controller, in FastAPI's thread pool, never on the event loop.
    @router.get(METRICS_PATH, summary="Prometheus metrics of the pendant and its arm")
    def get_metrics() -> Response:
        return Response(metrics.exposition(), media_type=CONTENT_TYPE_LATEST)

    return router
