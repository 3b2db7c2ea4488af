"""How results and errors look on the wire.

The reference gives two kinds of bodies:

- JSON documents (Position, Pose, Tool, the motor status array) served as `application/json`;
- "String" results (motion status, signal levels, recover result, robot ID) and every error message, served as
  `text/plain`. Their body is a JSON string literal, quotes included: `"IDLE"`, `"HIGH"`, `"SUCCESS"`,
  `"Robot does not respond"`. That is exactly how the reference prints them, it is what Rozum's SDK (`pdhttp`)
  reads best (it `json.loads` every body and falls back to the raw text, so `"12345"` stays the string
  `12345`, where a bare `12345` would come back as a number), and a curl user sees the same text as in the
  manual (`jq -r .` strips the quotes when a script needs the bare word).

Commands with nothing to return (`PUT /pose`, `/relax`, `/signal/output/1/high`, ...) answer 200 with an empty
`text/plain` body, as the reference's "200 OK: -".

Responses are built from bytes directly (pydantic-core's serialiser for models): no second validation pass,
which keeps the hot reads cheap.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from datetime import UTC, datetime

from pydantic import BaseModel, TypeAdapter
from starlette.responses import JSONResponse, Response

from pendant.controller.types import MotorStatus

TEXT = "text/plain"
JSON = "application/json"

_MOTORS = TypeAdapter(list[MotorStatus])


class TextResponse(Response):
    """A `text/plain` response (a JSON string literal, or empty)."""

    media_type = TEXT


class JSONBytesResponse(JSONResponse):
    """An `application/json` response whose body is already serialised (bytes pass through as they are)."""

    def render(self, content: object) -> bytes:
        return content if isinstance(content, bytes) else super().render(content)


def text_literal(text: str) -> bytes:
    """`IDLE` -> `"IDLE"`: the body of every string result and error message."""
    return json.dumps(text, ensure_ascii=False).encode()


def string_result(text: str, status_code: int = 200) -> TextResponse:
    return TextResponse(text_literal(text), status_code=status_code)


def empty_result() -> TextResponse:
    return TextResponse(b"")


def model_result(model: BaseModel) -> JSONBytesResponse:
    return JSONBytesResponse(model.__pydantic_serializer__.to_json(model))


def iso_time(epoch_s: float) -> str:
    """SDK >= 1.8's `timestamp`: ISO 8601, UTC, milliseconds."""
    return datetime.fromtimestamp(epoch_s, UTC).isoformat(timespec="milliseconds")


def timestamped_result(model: BaseModel, epoch_s: float) -> JSONBytesResponse:
    """`model`'s JSON object with a `timestamp` field added (GET /pose, GET /position)."""
    body = model.__pydantic_serializer__.to_json(model)
    stamp = json.dumps(iso_time(epoch_s)).encode()
    return JSONBytesResponse(body[:-1] + b',"timestamp":' + stamp + b"}")


def json_result(value: object) -> JSONBytesResponse:
    """Any JSON value as `application/json` (a bare string for GET /status, a number for /motors-log)."""
    return JSONBytesResponse(json.dumps(value).encode())


def models_result(models: Sequence[BaseModel]) -> JSONBytesResponse:
    return JSONBytesResponse(b"[" + b",".join(m.__pydantic_serializer__.to_json(m) for m in models) + b"]")


def motors_result(motors: Sequence[MotorStatus]) -> JSONBytesResponse:
    return JSONBytesResponse(_MOTORS.dump_json(list(motors)))
