"""The page's port refuses page loads and websocket upgrades that name a foreign Host or come from a page of
another Origin (pendant.access.origin), before viser sees them.

viser 1.1.1 builds its websockets server inside `ViserServer(...)` (viser/infra/_infra.py) with
`process_request=viser_http_server` and offers no hook of its own. `guarded_viser_server` wraps
`websockets.asyncio.server.serve` only while a ViserServer is being built (its constructor waits until the
server listens), putting the policy in front of whatever `process_request` viser (or another wrapper, such
as a customised page) passes: the hook composes, and nothing else is patched. Its HTTP answers also say that
no page of another origin may frame the pendant (clickjacking: a framed pendant has the pendant's own origin).
"""

from __future__ import annotations

import contextlib
import inspect
import threading
from collections.abc import Awaitable, Callable, Iterator
from typing import Any

import websockets.asyncio.server as ws_server
from websockets.asyncio.server import ServerConnection
from websockets.http11 import Request, Response

from pendant.access.origin import OriginPolicy

ProcessRequest = Callable[[ServerConnection, Request], Awaitable[Response | None] | Response | None]
ProcessResponse = Callable[
    [ServerConnection, Request, Response], Awaitable[Response | None] | Response | None
]
# Only the pendant's own pages may frame it.
NO_FOREIGN_FRAMES = (("Content-Security-Policy", "frame-ancestors 'self'"), ("X-Frame-Options", "SAMEORIGIN"))

_patching = threading.Lock()  # one ViserServer built under the wrapper at a time

# A browser whose connection is lost without a close (a cable pulled, a laptop asleep) is let go after at most
# PING_INTERVAL_S + PING_TIMEOUT_S + CLOSE_TIMEOUT_S (about 5 s), not websockets' default 20 + 20 + 10 s: the
# run it supervises pauses, its control passes on. The browser's network stack answers pings, not its
# (possibly stalled) main thread, so a slow page is not taken for a lost one; the margin is for a busy
# pendant's event loop.
PING_INTERVAL_S = 1.0
PING_TIMEOUT_S = 3.0
CLOSE_TIMEOUT_S = 1.0


def _one(request: Request, name: str) -> str | None:
    """The header's value; several values are joined, which no rule accepts (no browser sends two)."""
    values = request.headers.get_all(name)
    return ", ".join(values) if values else None


def guard_process_request(policy: OriginPolicy, inner: ProcessRequest | None) -> ProcessRequest:
    """`inner` behind the policy: a refused handshake gets a `text/plain` 403 and never reaches it."""

    async def process_request(connection: ServerConnection, request: Request) -> Response | None:
        refusal = policy.handshake_refusal(_one(request, "Host"), _one(request, "Origin"))
        if refusal is not None:
            status, message = refusal
            return connection.respond(status, message + "\n")
        if inner is None:
            return None
        answer = inner(connection, request)
        return await answer if inspect.isawaitable(answer) else answer

    return process_request


def guard_process_response(inner: ProcessResponse | None) -> ProcessResponse:
    """`inner`, then the anti-framing headers on every plain HTTP answer (the page and its files)."""

    async def process_response(
        connection: ServerConnection, request: Request, response: Response
    ) -> Response | None:
        if inner is not None:
            answer = inner(connection, request, response)
            replaced = await answer if inspect.isawaitable(answer) else answer
            response = replaced if replaced is not None else response
        if response.status_code != 101:  # a websocket's switch has no page to frame
            for name, value in NO_FOREIGN_FRAMES:
                response.headers[name] = value
        return response

    return process_response


Wrap = Callable[[ProcessRequest | None], ProcessRequest]


@contextlib.contextmanager
def guarded_viser_server(policy: OriginPolicy | None, wrap: Wrap | None = None) -> Iterator[None]:
    """While open, a websockets server started (by viser) gets `wrap` around its process_request (the
    pendant's page, say) and `policy` in front of everything, so no request skips the guard; and it lets go
    of a silent connection within about 5 s (PING_INTERVAL_S + PING_TIMEOUT_S + CLOSE_TIMEOUT_S)."""
    if policy is None and wrap is None:
        yield
        return
    with _patching:
        original = ws_server.serve

        def serve(
            handler: Any,
            *args: Any,
            process_request: ProcessRequest | None = None,
            process_response: ProcessResponse | None = None,
            **kwargs: Any,
        ) -> Any:
            if wrap is not None:
                process_request = wrap(process_request)
            if policy is not None:
                process_request = guard_process_request(policy, process_request)
                process_response = guard_process_response(process_response)
            kwargs.setdefault("ping_interval", PING_INTERVAL_S)
            kwargs.setdefault("ping_timeout", PING_TIMEOUT_S)
            kwargs.setdefault("close_timeout", CLOSE_TIMEOUT_S)
            return original(
                handler, *args, process_request=process_request, process_response=process_response, **kwargs
            )

        ws_server.serve = serve  # type: ignore[misc,assignment]  # patching the module's function for this scope
        try:
            yield
        finally:
            ws_server.serve = original  # type: ignore[misc]  # as above: put the module's own back
