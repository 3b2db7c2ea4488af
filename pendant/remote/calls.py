"""The remote client's one generic request: an operations-table row in, its typed answer out.

`call("GET /robot/info")` sends the row's method to its path (template parameters filled in and quoted) and
reads the answer as the row says: nothing, a string converted to the row's type (`MotionStatus`, ...), or a
JSON document validated as the row's model. RemoteController's typed methods are thin wrappers naming a row.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, TypeVar
from urllib.parse import quote

import httpx
from pydantic import TypeAdapter

from pendant.controller.operations import Operation, Reply, operation
from pendant.remote.wire import decode_text

T = TypeVar("T")

_ADAPTERS: dict[str, TypeAdapter[Any]] = {}  # by row key and result: built once, used on every call


class OperationCalls:
    """`call(key, ...)` over RemoteController's transport (`_request`, `_parse`)."""

    def _request(
        self,
        method: str,
        path: str,
        *,
        json: Any = None,
        params: Mapping[str, str | int | float] | None = None,
    ) -> httpx.Response:
        raise NotImplementedError  # RemoteController's

    def _parse(self, response: httpx.Response, request_line: str, parse: Callable[[bytes], T]) -> T:
        raise NotImplementedError  # RemoteController's

    def call(
        self,
        key: str,
        *,
        path: Mapping[str, str | int] | None = None,
        json: Any = None,
        params: Mapping[str, str | int | float] | None = None,
        result: Any = None,
    ) -> Any:
        """Send the operation `key` (`METHOD /path` as in the table) and return its answer as the row types
        it. `path`: the template's parameters; `json`: the body (wire form); `params`: the query; `result`:
        read a JSON answer as this type instead of the row's (an older firmware's shape)."""
        op = operation(key)
        target = op.path.format(**{name: quote(str(value), safe="") for name, value in (path or {}).items()})
        response = self._request(op.method, target, json=json, params=params)
        if op.reply is Reply.EMPTY:
            return None
        return self._parse(response, f"{op.method} {target}", _reader(op, result))


def _reader(op: Operation, result: Any) -> Callable[[bytes], Any]:
    if op.reply is Reply.TEXT:
        convert = result or op.result
        return lambda body: convert(decode_text(body))
    name = f"{op.key} {result!r}"
    adapter = _ADAPTERS.get(name)
    if adapter is None:
        adapter = _ADAPTERS[name] = TypeAdapter(result or op.result)
    return adapter.validate_json
