"""The pendant's API port in robot mode: a transparent proxy to the real PULSE controller.

Every request outside /pendant/ (the pendant's own namespace, e.g. GET /pendant/health) goes to the
controller with its method, path, query string, body and headers (minus hop-by-hop ones); the controller's
status, headers (content type included) and body come back byte for byte.

How a request is forwarded is its operations-table row's `forwarding` (pendant.controller.operations: a read,
a command or a stop); a path outside the table goes by its method (GET, HEAD, OPTIONS are reads).

Timeouts (the pendant's own, Settings / `--connect-timeout`, `--read-timeout`, `--command-timeout`):
- reads (GET, HEAD, OPTIONS) wait the short read timeout; a GET is retried once on a fresh connection when a
  kept-alive one turns out to be dead; no answer: 502 Bad Gateway with a `text/plain` reason.
- commands (every other method) wait the longer command timeout, since a controller under load may answer
  late and a command answered 502 that then ran in full would be sent twice by a client that retries. A
  command that could not be delivered (no connection) is 502: it did not run. A command sent whose answer was
  lost (no answer in time, or the connection closed) is 504 "No answer from the controller: the command may
  have run": read the arm's state before sending it again.
Nothing is queued or re-sent later.

A stop (`PUT /freeze`, `POST /stop`) goes up bare: no body, no content type, no page headers (`Origin`,
`Referer`, `Sec-Fetch-*`), whatever form it came in: the controller cannot refuse it for its form either.

Run alone (`pendant --robot URL` builds the same app):
    python -m pendant.remote.proxy --robot http://192.168.1.50:8081 --port 8081

The pendant also answers GET /metrics itself (Prometheus expects that path; it is not a PULSE one).
"""

from __future__ import annotations

import argparse
import contextlib
import time
from collections.abc import AsyncIterator, Callable
from urllib.parse import urlsplit

from fastapi import FastAPI
from starlette.requests import Request
from starlette.responses import PlainTextResponse, Response
from starlette.types import ASGIApp, Receive, Scope, Send

from pendant.access.http_guard import AccessGuard, AccessRules
from pendant.access.origin import OriginPolicy
from pendant.api.limits import BodySizeLimit
from pendant.api.stop_notice import StopNotice
from pendant.config import Settings
from pendant.controller.operations import Forwarding, forwarding
from pendant.controller.stops import StopBus
from pendant.monitoring import EventSource, PendantMetrics, add_monitoring
from pendant.remote.client import RemoteController
from pendant.remote.health import health_router
from pendant.remote.upstream import (
    UpstreamConnectError,
    UpstreamError,
    UpstreamPool,
    UpstreamResponse,
    UpstreamTimeout,
)

PENDANT_PREFIX = "/pendant/"  # served by the pendant itself, never forwarded
PENDANT_PATHS = ("/metrics",)  # the pendant's too (Prometheus expects this path), not a PULSE path
BAD_GATEWAY = 502
GATEWAY_TIMEOUT = 504
MSG_MAY_HAVE_RUN = "No answer from the controller: the command may have run"

# Headers that belong to one connection, not to the message (RFC 9110 7.6.1), plus the ones the proxy sets
# itself (host, content-length) or the server in front adds (date, server).
_HOP_BY_HOP = frozenset(
    {
        b"connection",
        b"keep-alive",
        b"proxy-authenticate",
        b"proxy-authorization",
        b"proxy-connection",
        b"te",
        b"trailer",
        b"transfer-encoding",
        b"upgrade",
    }
)
# `expect: 100-continue` was already answered by the server in front; the controller gets the whole body.
# The pendant's access token is the pendant's business: the controller never sees it.
_NOT_FORWARDED_UP = _HOP_BY_HOP | {b"host", b"content-length", b"expect", b"x-pendant-token"}
# What a stop leaves behind on its way up (its body is already dropped: pendant.api.limits).
_NOT_FORWARDED_WITH_A_STOP = _NOT_FORWARDED_UP | {b"content-type", b"origin", b"referer"}
_NOT_FORWARDED_DOWN = _HOP_BY_HOP | {b"content-length", b"date", b"server"}
_NO_BODY_STATUSES = frozenset({204, 304})

RequestHook = Callable[[Request], Response | None]
"""Called before each forwarded request, on the event loop (keep it fast). Return a Response to answer
instead of the controller (access control: a token check), or None to forward. An event log can record
`request.method`, `request.url.path` and `request.client` here."""


class _Forwarder:
    """ASGI middleware: forwards every HTTP request outside /pendant/ to the controller, raw."""

    def __init__(
        self,
        app: ASGIApp,
        robot_url: str,
        pool: UpstreamPool,
        on_request: RequestHook | None,
        command_timeout: float,
    ) -> None:
        self.app = app
        self.robot_url = robot_url
        self.pool = pool
        self.command_timeout = command_timeout
        self.on_request = on_request
        self.prefix = urlsplit(robot_url).path.rstrip("/").encode()

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if (
            scope["type"] != "http"
            or scope["path"].startswith(PENDANT_PREFIX)
            or scope["path"] in PENDANT_PATHS
        ):
            await self.app(scope, receive, send)
            return
        if self.on_request is not None:
            refusal = self.on_request(Request(scope, receive))
            if refusal is not None:
                await refusal(scope, receive, send)
                return
        body = b""
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":  # the caller gave up: send nothing on its behalf
                return
            body += message.get("body", b"")
            if not message.get("more_body", False):
                break
        method: str = scope["method"]
        target = self.prefix + (scope.get("raw_path") or scope["path"].encode())
        if scope["query_string"]:
            target += b"?" + scope["query_string"]
        headers = _headers_up(scope)
        answer = await self._exchange(method, target, headers, body, scope["path"])
        if isinstance(answer, Response):
            await answer(scope, receive, send)
            return
        response_headers = [(k, v) for k, v in answer.headers if k.lower() not in _NOT_FORWARDED_DOWN]
        if method == "HEAD":
            response_headers += [(k, v) for k, v in answer.headers if k.lower() == b"content-length"]
        elif answer.status >= 200 and answer.status not in _NO_BODY_STATUSES:
            response_headers.append((b"content-length", str(len(answer.body)).encode()))
        await send({"type": "http.response.start", "status": answer.status, "headers": response_headers})
        await send({"type": "http.response.body", "body": answer.body})

    async def _exchange(
        self, method: str, target: bytes, headers: list[tuple[bytes, bytes]], body: bytes, path: str
    ) -> UpstreamResponse | Response:
        """The controller's answer, or the 502/504 Response saying why there is none."""
        kind = forwarding(method, path)
        if kind is not Forwarding.READ:
            return await self._command(method, target, headers, body, path, urgent=kind is Forwarding.STOP)
        attempts = 2 if method == "GET" else 1
        for attempt in range(attempts):
            try:
                return await self.pool.request(method, target, headers, body, fresh=attempt > 0)
            except UpstreamTimeout as exc:
                return _bad_gateway(f"Controller at {self.robot_url} did not answer {method} {path}: {exc}")
            except UpstreamConnectError as exc:
                return _bad_gateway(f"Controller at {self.robot_url} is unreachable: {exc}")
            except UpstreamError as exc:
                if attempt + 1 == attempts:
                    return _bad_gateway(f"Controller at {self.robot_url} failed on {method} {path}: {exc}")
        raise AssertionError("unreachable")  # the loop always returns

    async def _command(
        self,
        method: str,
        target: bytes,
        headers: list[tuple[bytes, bytes]],
        body: bytes,
        path: str,
        *,
        urgent: bool,
    ) -> UpstreamResponse | Response:
        """Sent once, with the long timeout: 502 when it was never delivered, 504 when its answer was lost."""
        try:
            return await self.pool.request(
                method,
                target,
                headers,
                body,
                read_timeout=self.command_timeout,
                urgent=urgent,  # a stop never waits behind queued requests
            )
        except UpstreamConnectError as exc:
            return _bad_gateway(
                f"Controller at {self.robot_url} is unreachable: {exc} ({method} {path} not sent)"
            )
        except UpstreamError as exc:
            return PlainTextResponse(
                f"{MSG_MAY_HAVE_RUN} ({method} {path}: {exc})", status_code=GATEWAY_TIMEOUT
            )


def create_proxy_app(
    robot_url: str,
    *,
    settings: Settings | None = None,
    controller: RemoteController | None = None,
    on_request: RequestHook | None = None,
    connect_timeout: float | None = None,
    read_timeout: float | None = None,
    command_timeout: float | None = None,
    started_at: float | None = None,
    access: AccessRules | None = None,
    metrics: PendantMetrics | None = None,
    store: EventSource | None = None,
    stops: StopBus | None = None,
) -> FastAPI:
    """An ASGI app serving the PULSE API by forwarding to the controller at `robot_url` (plain HTTP), plus
    GET /pendant/health. More pendant routes can be added to it under /pendant/.

    `controller`: the RemoteController the rest of the pendant (UI, programs) uses, so that the health route
    probes and reports that very link; by default the app makes its own (closed with the app).
    `connect_timeout`, `read_timeout` (reads), `command_timeout` (everything else): seconds, by default the
    settings'. `access`: the pendant's guard (token, Host and Origin rules, Remote control), run first.
    `metrics`: served at GET /metrics (by default the app's own, reading the controller through the probe);
    `store`: the persistent event log, served at GET /pendant/events. `stops`: told of every stop request
    before it is forwarded (the page's held jog ends); what the arm then does is the controller's decision.
    """
    robot_url = robot_url.rstrip("/")
    parts = urlsplit(robot_url)
    if parts.scheme != "http" or not parts.hostname:
        raise ValueError(f"robot URL must look like http://HOST:8081, not {robot_url!r}")
    settings = settings if settings is not None else Settings(robot_url=robot_url)
    connect_timeout = connect_timeout if connect_timeout is not None else settings.connect_timeout
    read_timeout = read_timeout if read_timeout is not None else settings.read_timeout
    command_timeout = command_timeout if command_timeout is not None else settings.command_timeout
    started_at = started_at if started_at is not None else time.monotonic()
    pool = UpstreamPool(parts.hostname, parts.port or 80, connect_timeout, read_timeout)
    # The health probe is a blocking client: the health route runs in the thread pool.
    owns_probe = controller is None
    health_probe = controller or RemoteController(
        robot_url, connect_timeout=connect_timeout, read_timeout=read_timeout, get_retries=0
    )

    @contextlib.asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        try:
            yield
        finally:
            await pool.aclose()
            if owns_probe:
                health_probe.close()

    app = FastAPI(
        title="PULSE pendant (proxy to a real controller)",
        docs_url=None,
        redoc_url=None,
        openapi_url=None,
        lifespan=lifespan,
    )
    app.include_router(health_router(settings, health_probe, started_at))
    app.add_middleware(
        _Forwarder, robot_url=robot_url, pool=pool, on_request=on_request, command_timeout=command_timeout
    )
    if stops is not None:
        app.add_middleware(StopNotice, stops=stops)
    app.add_middleware(BodySizeLimit)  # no body, GET's included, is buffered past its limit
    if access is not None and access.active:
        app.add_middleware(AccessGuard, rules=access)  # /pendant/ routes included
    if metrics is None:
        metrics = PendantMetrics(health_probe, mode="robot", model=settings.model, robot_url=robot_url)
    add_monitoring(app, metrics, store)  # outermost: refusals are counted too
    app.state.robot_url = robot_url
    app.state.health_probe = health_probe
    app.state.upstream = pool  # its timeouts are the ones in force
    app.state.command_timeout = command_timeout
    return app


def _headers_up(scope: Scope) -> list[tuple[bytes, bytes]]:
    """The request's headers as the controller gets them (a stop's stripped down to the bare command)."""
    if forwarding(scope["method"], scope["path"]) is not Forwarding.STOP:
        return [(name, value) for name, value in scope["headers"] if name not in _NOT_FORWARDED_UP]
    return [
        (name, value)
        for name, value in scope["headers"]
        if name not in _NOT_FORWARDED_WITH_A_STOP and not name.startswith(b"sec-fetch-")
    ]


def _bad_gateway(message: str) -> Response:
    return PlainTextResponse(message, status_code=BAD_GATEWAY)


def main(argv: list[str] | None = None) -> int:
    """`python -m pendant.remote.proxy --robot URL [--host H] [--port N]`: the proxy alone, no UI."""
    from pendant.api.quitting import freeze_on_quit
    from pendant.api.serving import serve

    parser = argparse.ArgumentParser(description="Serve the PULSE API as a proxy to a real controller.")
    parser.add_argument("--robot", required=True, help="the controller's URL, e.g. http://192.168.1.50:8081")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8081)
    parser.add_argument("--connect-timeout", type=float, default=Settings.connect_timeout, metavar="S")
    parser.add_argument("--read-timeout", type=float, default=Settings.read_timeout, metavar="S")
    parser.add_argument("--command-timeout", type=float, default=Settings.command_timeout, metavar="S")
    args = parser.parse_args(argv)
    settings = Settings(
        host=args.host,
        api_port=args.port,
        robot_url=args.robot,
        no_ui=True,
        connect_timeout=args.connect_timeout,
        read_timeout=args.read_timeout,
        command_timeout=args.command_timeout,
    )
    app = create_proxy_app(args.robot, settings=settings, access=AccessRules(origins=OriginPolicy(args.host)))
    serve(app, args.host, args.port, freeze_on_quit(app.state.health_probe.freeze))  # quitting stops the arm
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
