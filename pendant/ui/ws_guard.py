"""The page's port refuses page loads and websocket upgrades that name a foreign Host or come from a page of
another Origin (pendant.access.origin), before viser sees them.

viser 1.1.1 builds its websockets server inside `ViserServer(...)` (viser/infra/_infra.py) with
`process_request=viser_http_server` and offers no hook of its own. `guarded_viser_server` wraps
`websockets.asyncio.server.serve` only while a ViserServer is being built (its constructor waits until the
server listens), putting the policy in front of whatever `process_request` viser (or another wrapper, such
as a customised page) passes: the hook composes, and nothing else is patched.
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

_patching = threading.Lock()  # one ViserServer built under the wrapper at a time


def guard_process_request(policy: OriginPolicy, inner: ProcessRequest | None) -> ProcessRequest:
    """`inner` behind the policy: a refused handshake gets a `text/plain` 403 and never reaches it."""

    async def process_request(connection: ServerConnection, request: Request) -> Response | None:
        refusal = policy.handshake_refusal(request.headers.get("Host"), request.headers.get("Origin"))
        if refusal is not None:
            status, message = refusal
            return connection.respond(status, message + "\n")
        if inner is None:
            return None
        answer = inner(connection, request)
        return await answer if inspect.isawaitable(answer) else answer

    return process_request


@contextlib.contextmanager
def guarded_viser_server(policy: OriginPolicy | None) -> Iterator[None]:
    """While open, a websockets server started (by viser) gets `policy` in front of its process_request."""
    if policy is None:
        yield
        return
    with _patching:
        original = ws_server.serve

        def serve(
            handler: Any, *args: Any, process_request: ProcessRequest | None = None, **kwargs: Any
        ) -> Any:
            return original(
                handler, *args, process_request=guard_process_request(policy, process_request), **kwargs
            )

        ws_server.serve = serve  # type: ignore[misc,assignment]
        try:
            yield
        finally:
            ws_server.serve = original  # type: ignore[misc]
