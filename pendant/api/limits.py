"""Request body size limits, enforced while the body streams in, before anything is buffered.

Every PULSE request body is small: the largest is a run of at most 100 waypoints. A client sending more is
refused with 413 and a `text/plain` message (a JSON string literal, like every PULSE error) naming the
limit, and the connection is closed so the rest of the upload is not read. The declared `Content-Length` is
checked before the first byte is read; a chunked body (no length) is counted as it arrives and refused the
moment it passes the limit. So no client can make the pendant hold or parse megabytes, which is what used
to delay PUT /freeze by seconds (issue #16).

The same middleware sits in front of the simulator's API and of the proxy to a real controller.
"""

from __future__ import annotations

from dataclasses import dataclass

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from pendant.api.wire import TEXT, text_literal
from pendant.controller.errors import ControllerError

KIB = 1024
# One pose, position, tool or base: a few hundred bytes; 8 KiB leaves room for pretty-printed JSON.
DOCUMENT_BODY_LIMIT = 8 * KIB
# A run: at most 100 waypoints (the controller's own limit), about 300 bytes each when pretty-printed.
RUN_BODY_LIMIT = 128 * KIB
# Anything else (reads and commands without a body, unknown paths): nothing is expected.
DEFAULT_BODY_LIMIT = 1 * KIB
# POST /pendant/preflight: a program (a file holds at most 5 MB) and a cell (at most 1 MB).
PREFLIGHT_BODY_LIMIT = 6_000_000

BODY_LIMITS: dict[tuple[str, str], int] = {
    ("PUT", "/position"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/pose"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/positions/run"): RUN_BODY_LIMIT,
    ("PUT", "/poses/run"): RUN_BODY_LIMIT,
    ("POST", "/tool"): DOCUMENT_BODY_LIMIT,
    ("POST", "/base"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/sim/pose"): DOCUMENT_BODY_LIMIT,
    # SDK 1.8.4: a tool (16 capsules at most), one obstacle (a plane of 16 points at most), a jog, and runs.
    ("POST", "/tool/info"): DOCUMENT_BODY_LIMIT,
    ("POST", "/tool/shape"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/environment"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/jogging"): DOCUMENT_BODY_LIMIT,
    ("PUT", "/run/linear/positions"): RUN_BODY_LIMIT,
    ("PUT", "/run/linear/poses"): RUN_BODY_LIMIT,
    ("PUT", "/run/joint/positions"): RUN_BODY_LIMIT,
    ("PUT", "/run/joint/poses"): RUN_BODY_LIMIT,
    ("POST", "/pendant/preflight"): PREFLIGHT_BODY_LIMIT,
}


def body_limit(method: str, path: str) -> int:
    """The largest body, in bytes, a request to `method path` may carry."""
    return BODY_LIMITS.get((method, path.rstrip("/") or "/"), DEFAULT_BODY_LIMIT)


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
                    message = {**message, "headers": [*message.get("headers", []), (b"connection", b"close")]}
            await send(message)

        try:
            await self.app(scope, counted_receive, closing_send)
        except PayloadTooLarge:
            if not stream.answered:  # an app without the API's error handlers (the proxy)
                await _send_too_large(send, stream.limit)


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
