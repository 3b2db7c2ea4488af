"""Request body size limits, enforced while the body streams in, before anything is buffered.

Every PULSE request body is small: the largest is a run of at most 100 waypoints. A client sending more is
refused with 413 and a `text/plain` message (a JSON string literal, like every PULSE error) naming the
limit, and the connection is closed so the rest of the upload is not read. The declared `Content-Length` is
checked before the first byte is read; a chunked body (no length) is counted as it arrives and refused the
moment it passes the limit. So no client can make the pendant hold or parse megabytes, which is what used
to delay PUT /freeze by seconds (issue #16).

A stop (`PUT /freeze`, `POST /stop`) is never refused for its body: its body is not read at all (the app
sees an empty one, the proxy forwards none) and, when one too large was announced, the connection is closed
after the answer so the rest of it is dropped.

The same middleware sits in front of the simulator's API and of the proxy to a real controller.
"""

from __future__ import annotations

from dataclasses import dataclass

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from pendant.api.wire import TEXT, text_literal
from pendant.controller.errors import ControllerError
from pendant.controller.operations import (
    BODY_LIMITS,
    DEFAULT_BODY_LIMIT,
    DOCUMENT_BODY_LIMIT,
    RUN_BODY_LIMIT,
    is_stop,
)

# Each operation's limit comes from the operations table (a document 8 KiB, a run 128 KiB, else 1 KiB).
__all__ = ["BODY_LIMITS", "DEFAULT_BODY_LIMIT", "DOCUMENT_BODY_LIMIT", "RUN_BODY_LIMIT", "BodySizeLimit"]
# The pendant's own routes beside the PULSE operations: a program to pre-flight (a file holds at most 5 MB)
# with its cell (at most 1 MB).
PENDANT_BODY_LIMITS: dict[tuple[str, str], int] = {("POST", "/pendant/preflight"): 6_000_000}


def body_limit(method: str, path: str) -> int:
    """The largest body, in bytes, a request to `method path` may carry."""
    key = (method, path.rstrip("/") or "/")
    return BODY_LIMITS.get(key) or PENDANT_BODY_LIMITS.get(key, DEFAULT_BODY_LIMIT)


def too_large_message(limit: int) -> str:
    return f"Request body too large: at most {limit} bytes for this request"


class PayloadTooLarge(ControllerError):
    """413: the body passed the request's limit (raised from `receive`, so the handler stops reading)."""

    status_code = 413

    def __init__(self, limit: int) -> None:
        super().__init__(too_large_message(limit))


@dataclass
class _Stream:
    """One request's progress: bytes received so far and whether the answer has started."""

    limit: int
    received: int = 0
    answered: bool = False


class BodySizeLimit:
    """ASGI middleware: refuse a request whose body is (or becomes) larger than its limit, with 413."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        stream = _Stream(body_limit(scope["method"], scope["path"]))
        declared = _content_length(scope)
        if is_stop(scope["method"], scope["path"]):
            answer = _closing(send) if (declared or 0) > stream.limit else send
            await self.app(scope, _without_body(receive), answer)
            return
        if declared is not None and declared > stream.limit:
            await _send_too_large(send, stream.limit)
            return

        async def counted_receive() -> Message:
            message = await receive()
            if message["type"] == "http.request":
                stream.received += len(message.get("body", b""))
                if stream.received > stream.limit:
                    raise PayloadTooLarge(stream.limit)
            return message

        async def closing_send(message: Message) -> None:
            if message["type"] == "http.response.start":
                stream.answered = True
                if message["status"] == PayloadTooLarge.status_code:  # the app's own 413: stop the upload
                    await _closing(send)(message)
                    return
            await send(message)

        try:
            await self.app(scope, counted_receive, closing_send)
        except PayloadTooLarge:
            if not stream.answered:  # an app without the API's error handlers (the proxy)
                await _send_too_large(send, stream.limit)


def _without_body(receive: Receive) -> Receive:
    """`receive` as a stop's handler sees it: an empty body at once (whatever was sent is never kept), then
    only the client's disconnection."""
    delivered = False

    async def receive_nothing() -> Message:
        nonlocal delivered
        if not delivered:
            delivered = True
            return {"type": "http.request", "body": b"", "more_body": False}
        while True:
            message = await receive()
            if message["type"] != "http.request":
                return message

    return receive_nothing


def _closing(send: Send) -> Send:
    """`send` with `connection: close` on the answer: the server then drops the unread body."""

    async def send_closing(message: Message) -> None:
        if message["type"] == "http.response.start":
            message = {**message, "headers": [*message.get("headers", []), (b"connection", b"close")]}
        await send(message)

    return send_closing


def _content_length(scope: Scope) -> int | None:
    for name, value in scope["headers"]:
        if name == b"content-length":
            try:
                return int(value)
            except ValueError:
                return None  # the HTTP server refuses a malformed length before the app sees it
    return None


async def _send_too_large(send: Send, limit: int) -> None:
    body = text_literal(too_large_message(limit))
    headers = [
        (b"content-type", f"{TEXT}; charset=utf-8".encode()),
        (b"content-length", str(len(body)).encode()),
        (b"connection", b"close"),  # the server then drops the rest of the upload instead of reading it
    ]
    await send({"type": "http.response.start", "status": PayloadTooLarge.status_code, "headers": headers})
    await send({"type": "http.response.body", "body": body})
