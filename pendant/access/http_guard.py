"""The API port's guard: one ASGI middleware in front of the simulator's PULSE API and of the proxy alike.

In order, for every HTTP request:
1. `Host` and, for commands, `Origin` and, for a page's commands other than stops, the content type
   (origin.OriginPolicy): 403 / 415. A request with neither `Origin` nor `Sec-Fetch-*` is no page's.
2. Reads (GET, HEAD, OPTIONS) go on. Every other method is a command (PROPFIND and MOVE too).
3. Stops (`PUT /freeze`, `POST /stop`) go on: stopping is open to every client, in any form.
4. The access token, when the pendant has one: 401 without it, 403 wrong; wrong guesses are slowed per
   client address (throttle.FailedAttempts: 429 when its turn is too far away).
5. The Remote control switch (remote.RemoteControl): 403 while the operator has it off, 409 while a jog is
   held in the page.
Each refusal is a `text/plain` JSON string literal, like every PULSE error. Accepted commands go to the event
log with their status; refusals once per burst per client (throttle.BurstLog).
"""

from __future__ import annotations

import asyncio
import json
from dataclasses import dataclass, field

from starlette.responses import Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from pendant.access.origin import OriginPolicy
from pendant.access.remote import RemoteControl
from pendant.access.throttle import BurstLog, FailedAttempts
from pendant.access.token import FORBIDDEN, TOKEN_HEADER, changes_robot, is_stop, token_refusal
from pendant.eventlog import EventKind, EventLog

_TOKEN_HEADER_BYTES = TOKEN_HEADER.lower().encode()
# Fetch metadata: every browser in use sends these (and `Origin` with a command); curl and urllib never do.
_FETCH_METADATA_PREFIX = b"sec-fetch-"
USER_AGENT_MAX_CHARS = 60
TOO_MANY_REQUESTS = 429


def refusal_response(status: int, message: str) -> Response:
    return Response(json.dumps(message), status_code=status, media_type="text/plain")


def describe_http_client(client: tuple[str, int] | None, user_agent: str | None) -> str:
    """`API 10.0.0.9 (python-requests/2.31)`: who sent a request, as the event log names it."""
    address = client[0] if client else "unknown address"
    agent = (user_agent or "no user agent")[:USER_AGENT_MAX_CHARS]
    return f"API {address} ({agent})"


@dataclass
class AccessRules:
    """What the guard enforces; None turns a rule off (e.g. no token on loopback)."""

    token: str | None = None
    events: EventLog | None = None
    origins: OriginPolicy | None = None
    remote: RemoteControl | None = None
    attempts: FailedAttempts = field(default_factory=FailedAttempts)
    bursts: BurstLog = field(default_factory=BurstLog)

    @property
    def active(self) -> bool:
        return any(rule is not None for rule in (self.token, self.events, self.origins, self.remote))


def _headers(scope: Scope) -> dict[bytes, bytes]:
    wanted = {b"host", b"origin", b"content-type", b"user-agent", _TOKEN_HEADER_BYTES}
    return {key: value for key, value in scope["headers"] if key in wanted}


def sent_by_page(scope: Scope) -> bool:
    """True when a browser sent the request for a page: it carries `Origin` or a `Sec-Fetch-*` header."""
    return any(key == b"origin" or key.startswith(_FETCH_METADATA_PREFIX) for key, _ in scope["headers"])


def _address(scope: Scope) -> str:
    client = scope.get("client")
    return client[0] if client else "unknown"


def _text(value: bytes | None) -> str | None:
    return value.decode("latin-1") if value is not None else None


class AccessGuard:
    """ASGI middleware enforcing `rules` (see the module's docstring)."""

    def __init__(self, app: ASGIApp, rules: AccessRules) -> None:
        self.app = app
        self.rules = rules

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        rules = self.rules
        method: str = scope["method"]
        changes = changes_robot(method)
        stop = is_stop(method, scope["path"])
        headers = _headers(scope) if changes or rules.origins is not None else {}
        if rules.origins is not None:
            refusal = rules.origins.request_refusal(
                _text(headers.get(b"host")),
                _text(headers.get(b"origin")),
                _text(headers.get(b"content-type")),
                changes=changes,
                from_page=changes and sent_by_page(scope),
                stop=stop,
            )
            if refusal is not None:
                await self._refuse(scope, receive, send, headers, refusal)
                return
        if not changes:
            await self.app(scope, receive, send)  # reads: no check, no log
            return
        if not stop:
            refusal = await self._token_refusal(scope, headers)
            if refusal is None and rules.remote is not None:
                refusal = rules.remote.begin_api_command()
                if refusal is None:
                    try:
                        await self.app(scope, receive, self._logging(scope, headers, send))
                    finally:
                        rules.remote.end_api_command()
                    return
            if refusal is not None:
                await self._refuse(scope, receive, send, headers, refusal)
                return
        await self.app(scope, receive, self._logging(scope, headers, send))

    async def _token_refusal(self, scope: Scope, headers: dict[bytes, bytes]) -> tuple[int, str] | None:
        token = self.rules.token
        if token is None:
            return None
        attempts = self.rules.attempts
        address = _address(scope)
        wait = attempts.wait_before_check(address)
        if wait is None:
            return TOO_MANY_REQUESTS, (
                f"Too many wrong access tokens from {address}: wait {attempts.max_wait_s:g} s and try again"
            )
        if wait > 0:
            await asyncio.sleep(wait)  # this client's turn: guesses are serialised per address
        refusal = token_refusal(scope["method"], scope["path"], headers.get(_TOKEN_HEADER_BYTES), token)
        if refusal is None:
            attempts.succeeded(address)
        elif refusal[0] == FORBIDDEN:
            attempts.failed(address)
        return refusal

    def _who(self, scope: Scope, headers: dict[bytes, bytes]) -> str:
        return describe_http_client(scope.get("client"), _text(headers.get(b"user-agent")))

    async def _refuse(
        self,
        scope: Scope,
        receive: Receive,
        send: Send,
        headers: dict[bytes, bytes],
        refusal: tuple[int, str],
    ) -> None:
        status, message = refusal
        events = self.rules.events
        if events is not None:
            who = self._who(scope, headers)
            unlogged = self.rules.bursts.note(
                _address(scope)
            )  # by address: a changing user agent is one client
            if unlogged is not None:
                more = (
                    f" ({unlogged} earlier refusals of this client not logged one by one)" if unlogged else ""
                )
                line = f"{scope['method']} {scope['path']}: {status} {message}{more}"
                events.record(EventKind.REFUSED, who, line)
        await refusal_response(status, message)(scope, receive, send)

    def _logging(self, scope: Scope, headers: dict[bytes, bytes], send: Send) -> Send:
        events = self.rules.events
        if events is None:
            return send
        who = self._who(scope, headers)
        method, path = scope["method"], scope["path"]

        async def send_and_log(message: Message) -> None:
            if message["type"] == "http.response.start":
                status = message["status"]
                kind = EventKind.COMMAND if status < 400 else EventKind.ERROR
                events.record(kind, who, f"{method} {path} -> {status}")
            await send(message)

        return send_and_log
