"""Routes registered from the operations table: `serve(router, "PUT /run/joint/poses", ...)` on a handler.

The row (pendant.controller.operations) gives the method and path, the documented request body (its model,
a list of it for a run of waypoints) and the 200 answer (empty, a string, or a JSON model) with the response
class that sends it; the handler gives what only it knows: the text (summary, description, examples) and the
errors it can answer. It reads its body with the row's model too: `read_body(request, body_of(key))`. A
handler that names no row fails at import (KeyError), and a row without a handler fails
tests/api/test_operations.py.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from typing import Annotated, Any, TypeVar, get_args, get_origin

from fastapi import APIRouter
from pydantic import Field, TypeAdapter
from starlette.responses import Response

from pendant.api import docs
from pendant.api.params import json_body
from pendant.api.wire import JSONBytesResponse, TextResponse
from pendant.controller.operations import Operation, Reply, operation

F = TypeVar("F", bound=Callable[..., Any])

_NO_EXAMPLE = object()


def serve(
    router: APIRouter,
    key: str,
    *,
    summary: str,
    description: str | None = None,
    ok: str = "Success (empty body)",
    example: Any = _NO_EXAMPLE,
    body_example: Any = None,
    body_description: str = "",
    errors: docs.Responses | None = None,
    response_class: type[Response] | None = None,
    convertors: dict[str, str] | None = None,
    **route: Any,
) -> Callable[[F], F]:
    """Register the decorated handler as the route of the row `key` (`METHOD /path`) on `router`.

    `ok`: the 200's description; `example`: its example (a JSON document, or the strings a text answer may
    carry); `body_example`, `body_description`: the request body's, for a row with one; `errors`: the other
    documented answers (a 200 there replaces the row's). `convertors`: Starlette path convertors for the
    template's parameters (`{"obstacle": "path"}`: a name with a slash). `route`: more of FastAPI's
    `add_api_route` keywords.
    """
    op = operation(key)

    def register(endpoint: F) -> F:
        # Where it comes from, whether it is a stop: a route registered elsewhere lacks them (a test sees it).
        extra = {"x-pulse-source": op.source.value, "x-pulse-stop": op.stop, **route.pop("openapi_extra", {})}
        if op.request is not None:
            extra = {**json_body(_body_schema(op), body_example, body_description), **extra}
        path = op.path.removeprefix(router.prefix)
        for name, convertor in (convertors or {}).items():
            path = path.replace(f"{{{name}}}", f"{{{name}:{convertor}}}")
        router.add_api_route(
            path,
            endpoint,
            methods=[op.method],
            summary=summary,
            description=description,
            response_class=response_class or (JSONBytesResponse if op.reply is Reply.JSON else TextResponse),
            responses={**answer(op, ok, example), **(errors or {})},
            openapi_extra=extra,
            **route,
        )
        return endpoint

    return register


_BODIES: dict[str, TypeAdapter[Any]] = {}


def body_of(key: str) -> TypeAdapter[Any]:
    """The parser of the row `key`'s request body (for `pendant.api.params.read_body`): the row's model, or
    a non-empty list of it (an empty run is 400, as the controller answers)."""
    adapter = _BODIES.get(key)
    if adapter is None:
        request = operation(key).request
        if request is None:
            raise KeyError(f"{key} takes no body")
        if get_origin(request) is list:
            request = Annotated[request, Field(min_length=1)]
        adapter = _BODIES[key] = TypeAdapter(request)
    return adapter


def answer(op: Operation, description: str, example: Any = _NO_EXAMPLE) -> docs.Responses:
    """The documented 200 of `op`, from its row's reply and result type."""
    if op.reply is Reply.EMPTY:
        return docs.empty_ok(description)
    if op.reply is Reply.JSON:
        return docs.json_ok(op.result, description, None if example is _NO_EXAMPLE else example)
    examples: tuple[str, ...] = () if example is _NO_EXAMPLE else tuple(example)
    result = op.result
    if isinstance(result, type) and issubclass(result, Enum):
        values = [member.value for member in result]
        return docs.text_ok(description, {"type": "string", "enum": values}, *(examples or values))
    return docs.text_ok(description, {"type": "string"}, *examples)


def _body_schema(op: Operation) -> dict[str, Any]:
    assert op.schema is not None
    if get_origin(op.request) is list:
        return docs.waypoints(get_args(op.request)[0].__name__)
    return docs.ref(op.schema)
