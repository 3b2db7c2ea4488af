"""The PULSE wire format as a client sees it: plain-text bodies and status codes -> typed errors."""

from __future__ import annotations

import json

from pendant.controller.errors import (
    ERRORS_BY_STATUS,
    MSG_COLLISION,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    Collision,
    ControllerError,
    ControllerOffline,
    PreconditionFailed,
    Unreachable,
    Unsupported,
)
from pendant.controller.operations import Source, find_operation

_MAX_QUOTED_BODY = 200  # characters of an unexpected body quoted in an error message


def decode_text(body: bytes) -> str:
    """A plain-text answer as text. The controller may send `"IDLE"` (a JSON string) or `IDLE` (raw text);
    both give `IDLE`. A JSON object with a `detail` (FastAPI's default error shape) gives the detail."""
    text = body.decode("utf-8", errors="replace").strip()
    if not text or text[0] not in '"{':
        return text
    try:
        value = json.loads(text)
    except ValueError:
        return text
    if isinstance(value, str):
        return value.strip()
    if isinstance(value, dict) and "detail" in value:
        detail = value["detail"]
        return detail if isinstance(detail, str) else json.dumps(detail)
    return text


def quote_body(body: bytes) -> str:
    """A short printable excerpt of an unexpected body, for error messages."""
    text = body.decode("utf-8", errors="replace")
    return repr(text if len(text) <= _MAX_QUOTED_BODY else text[:_MAX_QUOTED_BODY] + "...")


def error_for_status(status_code: int, body: bytes, request_line: str) -> ControllerError:
    """The typed error for a non-2xx answer, carrying the controller's own message.

    412 is split by message (Collision, Unreachable, else PreconditionFailed); statuses the PULSE API never
    uses (404, 405, 422, 502, ...) mean we are not talking to a working PULSE controller: ControllerOffline,
    but a 404 to an SDK 1.8 operation is Unsupported (older firmware).
    """
    message = decode_text(body)
    if status_code == 412:
        if message == MSG_COLLISION or message.startswith(f"{MSG_COLLISION}: "):  # "...: what it touches"
            return Collision(message)
        if message in (MSG_UNREACHABLE_POSITION, MSG_UNREACHABLE_POSE):
            return Unreachable(message)
        return PreconditionFailed(message or None)
    error_type = ERRORS_BY_STATUS.get(status_code)
    if error_type is not None:
        return error_type(message or None)
    # A 404 to one of SDK 1.8.4's operations beyond the reference guide is a working controller with older
    # firmware (the page greys that feature out), not a server that is no PULSE controller at all.
    method, _, target = request_line.partition(" ")
    operation = find_operation(method, target.partition("?")[0])
    if status_code == 404 and operation is not None and operation.source is Source.SDK_1_8:
        return Unsupported(f"The controller does not support {request_line} (HTTP 404: older firmware)")
    return ControllerOffline(
        f"Unexpected answer from the controller to {request_line}: HTTP {status_code} {quote_body(body)}"
    )
