"""The one table of PULSE operations (pendant.controller.operations) and what is really served: every route
is in the table and every entry has a route, with the documented body and answer it declares; the remote
client's generic request sends each row and reads its answer as the row types it; the proxy forwards each as
the row says; its stops are what the access guard opens to everyone, its bodies what the size limits allow,
its SDK 1.8.4 entries what the remote client recognises as newer firmware."""

from __future__ import annotations

from enum import Enum
from typing import Any, get_args, get_origin

import httpx
import pytest
from fastapi.testclient import TestClient
from pydantic import BaseModel, TypeAdapter

from pendant.access.token import is_stop as guard_is_stop
from pendant.api import create_app
from pendant.api.availability import NOT_THE_CONTROLLERS
from pendant.api.limits import body_limit
from pendant.controller.errors import Unsupported
from pendant.controller.operations import (
    DEFAULT_BODY_LIMIT,
    OPERATIONS,
    Body,
    Forwarding,
    Operation,
    Reply,
    Source,
    find_operation,
    forwarding,
)
from pendant.remote import RemoteController
from pendant.remote.wire import error_for_status
from pendant.sim import FakeClock, SimController
from tests.support.obstacles import box

NOT_PULSE = {"/docs", "/docs/oauth2-redirect", "/redoc", "/openapi.json"}


@pytest.fixture(scope="module")
def schema() -> dict[str, Any]:
    return create_app(SimController("pulse75", FakeClock())).openapi()


def _served(schema: dict[str, Any]) -> set[tuple[str, str]]:
    return {(method.upper(), path) for path, item in schema["paths"].items() for method in item}


def test_every_route_is_in_the_table_and_every_entry_is_served(schema: dict[str, Any]) -> None:
    table = {(op.method, op.path) for op in OPERATIONS}
    served = _served(schema) - {("GET", path) for path in NOT_PULSE}
    assert served - table == set(), "routes the table does not name"
    assert table - served == set(), "table entries without a route"
    assert len(table) == len(OPERATIONS), "an operation is declared twice"


def test_the_documented_body_is_the_one_the_table_declares(schema: dict[str, Any]) -> None:
    for op in OPERATIONS:
        body = schema["paths"][op.path][op.method.lower()].get("requestBody")
        if op.schema is None:
            assert body is None, op
            continue
        documented = body["content"]["application/json"]["schema"]
        if op.schema.endswith("[]"):
            assert documented["type"] == "array", op
            documented = documented["items"]
        assert documented["$ref"].rsplit("/", 1)[1] == op.schema.removesuffix("[]"), op


def test_the_stops_are_the_tables_and_only_they_skip_the_checks() -> None:
    stops = {(op.method, op.path) for op in OPERATIONS if op.stop}
    assert stops == {("PUT", "/freeze"), ("POST", "/stop")}
    for op in OPERATIONS:
        assert guard_is_stop(op.method, op.path) == op.stop, op
    assert not guard_is_stop("DELETE", "/stop")  # unbinding the stop is a command like any other


def test_body_limits_follow_the_table() -> None:
    for op in OPERATIONS:
        expected = DEFAULT_BODY_LIMIT if op.body is Body.NONE else op.body_limit
        assert body_limit(op.method, op.path) == expected, op
    assert body_limit("PUT", "/no/such/operation") == DEFAULT_BODY_LIMIT


def test_a_404_to_an_sdk_operation_means_older_firmware_and_to_a_guide_one_no_controller() -> None:
    for op in OPERATIONS:
        if op.source is Source.SIMULATOR:
            continue
        path = op.path.replace("{port}", "1").replace("{obstacle}", "box")
        error = error_for_status(404, b'"Not Found"', f"{op.method} {path}")
        assert isinstance(error, Unsupported) == (op.source is Source.SDK_1_8), op


def test_the_docs_say_where_each_operation_comes_from_and_which_are_stops(schema: dict[str, Any]) -> None:
    for op in OPERATIONS:
        documented = schema["paths"][op.path][op.method.lower()]
        assert (documented["x-pulse-source"], documented["x-pulse-stop"]) == (op.source.value, op.stop)


def test_the_pendants_own_operations_are_the_ones_it_answers_without_a_controller() -> None:
    for op in OPERATIONS:
        assert op.path.startswith(NOT_THE_CONTROLLERS) == (not op.controller), op


def test_find_operation_reads_templates() -> None:
    found = find_operation("PUT", "/signal/output/2/high")
    assert found is not None and found.path == "/signal/output/{port}/high"
    assert find_operation("PUT", "/signal/output/2/middle") is None
    assert find_operation("GET", "/freeze") is None


def test_the_pendant_answers_its_own_operations_in_emergency_and_the_controllers_do_not() -> None:
    sim = SimController("pulse75", FakeClock())
    with TestClient(create_app(sim)) as client:
        client.put("/sim/fault/emergency")
        assert client.get("/status/motion").status_code == 503
        for op in OPERATIONS:
            if op.method == "GET" and "{" not in op.path:
                status = client.get(op.path).status_code
                answers = op.in_emergency or not op.controller
                assert (status != 503) == answers, (op, status)


_REF = "#/components/schemas/{model}"


def _expected_schema(result: Any) -> dict[str, Any]:
    """The OpenAPI schema of a JSON answer of type `result`, as FastAPI documents it (titles aside)."""
    if isinstance(result, type) and issubclass(result, BaseModel):
        return {"$ref": _REF.format(model=result.__name__)}
    if get_origin(result) is list:
        return {"type": "array", "items": _expected_schema(get_args(result)[0])}
    schema = TypeAdapter(result).json_schema(ref_template=_REF)
    schema.pop("$defs", None)
    return schema


def _untitled(schema: dict[str, Any]) -> dict[str, Any]:
    return {
        key: _untitled(value) if isinstance(value, dict) else value
        for key, value in schema.items()
        if key != "title"
    }


def test_the_documented_answer_is_the_one_the_table_declares(schema: dict[str, Any]) -> None:
    for op in OPERATIONS:
        (media_type, content), *others = schema["paths"][op.path][op.method.lower()]["responses"]["200"][
            "content"
        ].items()
        assert others == [], op
        documented = content["schema"]
        if op.reply is Reply.EMPTY:
            assert (media_type, documented) == ("text/plain", {"type": "string", "maxLength": 0}), op
        elif op.reply is Reply.TEXT:  # a JSON string literal (GET /status sends it as application/json)
            assert documented["type"] == "string" and "maxLength" not in documented, op
            if isinstance(op.result, type) and issubclass(op.result, Enum):
                assert documented["enum"] == [member.value for member in op.result], op
        else:
            assert media_type == "application/json", op
            assert _untitled(documented) == _expected_schema(op.result), op


def _filled(op: Operation) -> dict[str, str | int]:
    values: dict[str, str | int] = {"port": 1, "obstacle": "far box", "fault": "emergency"}
    return {name: value for name, value in values.items() if f"{{{name}}}" in op.path}


MOVES_THROUGH_POSITIONS = {"PositionWaypoint", "PositionWaypoint[]", "LinearPositions", "JointPositions"}


def _here(example: Any, position: dict[str, Any]) -> Any:
    """The documented example body with every position in it moved to where the arm is (no collision)."""
    if isinstance(example, list):
        return [_here(item, position) for item in example]
    if isinstance(example, dict):
        if "point" in example and "rotation" in example:
            return {**example, **position}
        return {key: _here(value, position) for key, value in example.items()}
    return example


def test_the_remote_client_sends_every_row_and_reads_its_answer_as_the_row_types_it(
    schema: dict[str, Any],
) -> None:
    sim = SimController("pulse75", FakeClock())
    with TestClient(create_app(sim)) as client:
        remote = RemoteController(str(client.base_url), client=client)
        answers: list[httpx.Response] = []
        client.event_hooks["response"] = [answers.append]
        for op in OPERATIONS:
            client.put("/sim/reset")
            client.put("/environment", json=box("far box", (2.0, 2.0, 2.0)).model_dump(mode="json"))
            if op.path == "/sim/pose":
                client.put("/relax")  # the arm is moved by hand only when relaxed
            here = client.get("/position").json()
            here = {"point": here["point"], "rotation": here["rotation"]}
            body = schema["paths"][op.path][op.method.lower()].get("requestBody")
            example = None if body is None else body["content"]["application/json"]["example"]
            if op.schema in MOVES_THROUGH_POSITIONS:
                example = _here(example, here)
            answer = remote.call(op.key, path=_filled(op), json=example)
            sent = answers[-1]
            assert (sent.request.method, sent.status_code) == (op.method, 200), op
            assert op.matches(sent.request.method, sent.request.url.path), op
            media_type = sent.headers["content-type"].partition(";")[0]
            if op.reply is Reply.EMPTY:
                assert (answer, sent.read()) == (None, b""), op
            elif op.reply is Reply.TEXT:  # a JSON string literal; GET /status labels it application/json
                assert media_type in ("text/plain", "application/json"), op
                assert sent.json() == answer == op.result(answer) != "", op
            else:  # the row's type reads the whole answer: a field it lacks would be lost here
                assert media_type == "application/json", op
                adapter = TypeAdapter(op.result)
                assert adapter.dump_python(answer, mode="json", by_alias=True) == sent.json(), op


def test_the_proxy_forwards_each_row_as_a_read_a_command_or_a_stop() -> None:
    for op in OPERATIONS:
        path = op.path.replace("{port}", "1").replace("{obstacle}", "box").replace("{fault}", "emergency")
        expected = (
            Forwarding.STOP if op.stop else Forwarding.READ if op.method == "GET" else Forwarding.COMMAND
        )
        assert forwarding(op.method, path) is expected, op
    assert forwarding("HEAD", "/pose") is Forwarding.READ  # outside the table: by its method
    assert forwarding("PUT", "/no/such/operation") is Forwarding.COMMAND
