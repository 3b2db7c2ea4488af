"""Property-based fuzzing of the PULSE API against its own OpenAPI document (schemathesis + hypothesis).

For generated valid and invalid requests to every PULSE operation: no 5xx but the documented 500/503 with
their messages, nothing FastAPI-ish (422), every answer matches the documented status codes, content types and
schemas, the server keeps serving, and a refused (4xx) request leaves the arm as it was.
"""

from __future__ import annotations

import json
import resource
import time
from collections.abc import Iterator
from typing import Any

import pytest
import schemathesis
from fastapi.testclient import TestClient
from hypothesis import HealthCheck, settings
from schemathesis import GenerationMode
from schemathesis.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)
from schemathesis.core.parameters import ParameterLocation

from pendant.api import create_app
from pendant.controller.errors import MSG_EMERGENCY, MSG_NOT_RESPONDING
from pendant.sim import FakeClock, SimController

pytestmark = pytest.mark.slow

EXAMPLES_PER_OPERATION = 30
FUZZ_BUDGET_S = 50.0  # the whole fuzz run; examples past it pass without a request
CLOCK_STEP_S = 0.25  # let queued motions progress between requests, as real time would
# 413: a body over the operation's documented size limit, refused before it is read (pendant/api/limits.py).
REFUSALS = {400, 405, 412, 413}
MEMORY_HEADROOM_BYTES = 2 * 1024**3
DOCUMENTED_SERVER_ERRORS = {500: json.dumps(MSG_NOT_RESPONDING), 503: json.dumps(MSG_EMERGENCY)}

clock = FakeClock()
sim = SimController(clock=clock)
app = create_app(sim)
schema = schemathesis.openapi.from_asgi("/openapi.json", app).exclude(path_regex="^/sim/")
# Unknown query parameters are ignored, as the controller does: do not send them as "invalid" requests.
schema.config.generation.update(modes=list(GenerationMode), allow_extra_parameters=False)
probe = TestClient(app)
started_at: list[float] = []


@pytest.fixture(autouse=True)
def memory_guard() -> Iterator[None]:
    """Cap this process's address space while fuzzing: a request that makes the simulator allocate without
    bound must fail here as a MemoryError, not drive the shared machine out of memory."""
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    with open("/proc/self/statm") as statm:
        in_use = int(statm.read().split()[0]) * resource.getpagesize()
    cap = in_use + MEMORY_HEADROOM_BYTES
    resource.setrlimit(resource.RLIMIT_AS, (cap if hard == resource.RLIM_INFINITY else min(cap, hard), hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def arm_state() -> tuple[Any, ...]:
    """Everything a request could change, read from the simulator itself."""
    return (
        sim.get_pose(),
        sim.get_position(),
        sim.get_tool(),
        sim.get_base(),
        sim.get_motion_status(),
        tuple(sim.get_output(port) for port in (1, 2)),
        sim.joint_positions().tolist(),
        sim.gripper_opening(),
    )


def is_invalid(case: schemathesis.Case) -> bool:
    """Whether schemathesis made the request invalid on purpose, other than by its Content-Type (the API reads
    the body as JSON whatever the header says: `curl -d` sends form encoding)."""
    if case.meta is None or case.meta.generation.mode is not GenerationMode.NEGATIVE:
        return False
    negative = {
        location for location, info in case.meta.components.items() if info.mode is GenerationMode.NEGATIVE
    }
    if negative == {ParameterLocation.HEADER}:
        return False
    # An object or array in the query is sent exploded (`timeout={"0": null}` goes out as `0=null`): the
    # request then carries unknown parameters, ignored, not an invalid documented one.
    exploded = any(isinstance(value, dict | list) for value in (case.query or {}).values())
    return not (negative == {ParameterLocation.QUERY} and exploded)


def over_budget() -> bool:
    if not started_at:
        started_at.append(time.monotonic())
    return time.monotonic() - started_at[0] > FUZZ_BUDGET_S


@schema.parametrize()
@settings(
    max_examples=EXAMPLES_PER_OPERATION,
    deadline=None,
    derandomize=True,  # the same requests on every run: a failure here is a bug, never bad luck
    suppress_health_check=list(HealthCheck),
)
def test_the_api_keeps_its_contract(case: schemathesis.Case) -> None:
    if over_budget():
        return
    clock.advance(CLOCK_STEP_S)
    before = arm_state()
    response = case.call()

    assert response.status_code != 422
    if response.status_code >= 500:
        assert DOCUMENTED_SERVER_ERRORS.get(response.status_code) == response.text
    case.validate_response(
        response,
        checks=[
            status_code_conformance,
            content_type_conformance,
            response_schema_conformance,
        ],
    )
    if is_invalid(case):
        # Schemathesis' own negative_data_rejection does not know 412, the controller's "incorrect input
        # parameters": invalid requests must be refused with 400 (body), 412 (parameters), 405 (method) or
        # 413 (a generated body past the operation's size limit).
        assert response.status_code in REFUSALS, (
            f"invalid request accepted: {response.status_code} {case.method} {case.formatted_path} "
            f"{case.query} {case.body!r}"
        )
    if 400 <= response.status_code < 500:
        assert arm_state() == before, (
            f"{case.method} {case.path} answered {response.status_code}, changed the arm"
        )
    assert probe.get("/robot/id").status_code == 200, "the server stopped serving"
