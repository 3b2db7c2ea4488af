"""The token check and the event log on the HTTP side: an ASGI middleware for the simulator's PULSE API, and
the same check as the proxy's `on_request` hook in front of a real controller.

Reads (GET, HEAD, OPTIONS) pass untouched. Every request that can change the robot (PUT, POST, PATCH,
DELETE, /sim/... included) needs the `X-Pendant-Token` header when the pendant has a token: 401 without it,
403 with a wrong one, each with a `text/plain` message (a JSON string literal, like every PULSE error).
Accepted and refused commands go to the event log with the client's address and user agent.
"""

from __future__ import annotations

import json
from collections.abc import Callable

from starlette.requests import Request
from starlette.responses import Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from pendant.access.token import MUTATING_METHODS, TOKEN_HEADER, token_refusal
from pendant.eventlog import EventKind, EventLog

_TOKEN_HEADER_BYTES = TOKEN_HEADER.lower().encode()
USER_AGENT_MAX_CHARS = 60


def refusal_response(status: int, message: str) -> Response:
    return Response(json.dumps(message), status_code=status, media_type="text/plain")


def describe_http_client(client: tuple[str, int] | None, user_agent: str | None) -> str:
    """`API 10.0.0.9 (python-requests/2.31)`: who sent a request, as the event log names it."""
    address = client[0] if client else "unknown address"
    agent = (user_agent or "no user agent")[:USER_AGENT_MAX_CHARS]
    return f"API {address} ({agent})"


def _header(scope: Scope, name: bytes) -> str | None:
    for key, value in scope["headers"]:
        if key == name:
            return value.decode("latin-1")
    return None


class TokenGuard:
    """ASGI middleware: refuse mutating requests without the right token; log every mutating request."""

    def __init__(self, app: ASGIApp, token: str | None, events: EventLog | None) -> None:
        self.app = app
        self.token = token
        self.events = events

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope["method"] not in MUTATING_METHODS:
            await self.app(scope, receive, send)  # reads: no check, no log, no cost
            return
        method, path = scope["method"], scope["path"]
        who = describe_http_client(scope.get("client"), _header(scope, b"user-agent"))
        refusal = token_refusal(method, _header(scope, _TOKEN_HEADER_BYTES), self.token)
        if refusal is not None:
            status, message = refusal
            if self.events is not None:
                self.events.record(EventKind.REFUSED, who, f"{method} {path}: {status} {message}")
            await refusal_response(status, message)(scope, receive, send)
            return
        if self.events is None:
            await self.app(scope, receive, send)
            return
        events = self.events

        async def send_and_log(message: Message) -> None:
            if message["type"] == "http.response.start":
                status = message["status"]
                kind = EventKind.COMMAND if status < 400 else EventKind.ERROR
                events.record(kind, who, f"{method} {path} -> {status}")
            await send(message)

        await self.app(scope, receive, send_and_log)


def proxy_request_hook(token: str | None, events: EventLog | None) -> Callable[[Request], Response | None]:
    """The proxy's `on_request`: the same check and log in front of a real controller (the status the
    controller answers is not known yet here, so accepted commands are logged as sent)."""

    def on_request(request: Request) -> Response | None:
        method = request.method
        if method not in MUTATING_METHODS:
            return None
        who = describe_http_client(
            (request.client.host, request.client.port) if request.client else None,
            request.headers.get("user-agent"),
        )
        refusal = token_refusal(method, request.headers.get(TOKEN_HEADER), token)
        if refusal is not None:
            status, message = refusal
            if events is not None:
                events.record(EventKind.REFUSED, who, f"{method} {request.url.path}: {status} {message}")
            return refusal_response(status, message)
        if events is not None:
            events.record(EventKind.COMMAND, who, f"{method} {request.url.path}")
        return None

    return on_request
