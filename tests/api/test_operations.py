"""The one table of PULSE operations (pendant.controller.operations) and what is really served: every route
is in the table and every entry has a route, with the documented body it declares; its stops are what the
access guard opens to everyone, its bodies what the size limits allow, its SDK 1.8.4 entries what the
remote client recognises as newer firmware."""

from __future__ import annotations

from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.access.token import is_stop as guard_is_stop
from pendant.api import create_app
from pendant.api.availability import NOT_THE_CONTROLLERS
from pendant.api.limits import body_limit
from pendant.controller.errors import Unsupported
from pendant.controller.operations import (
    DEFAULT_BODY_LIMIT,
    OPERATIONS,
    Body,
    Source,
    find_operation,
)
from pendant.remote.wire import error_for_status
from pendant.sim import FakeClock, SimController

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
