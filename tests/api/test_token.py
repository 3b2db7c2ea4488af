"""The PULSE API of an exposed pendant: commands need the X-Pendant-Token header, reads stay open."""

from __future__ import annotations

import json

import numpy as np
import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient

from pendant.access import TOKEN_HEADER
from pendant.api import create_app
from pendant.eventlog import EventKind, EventLog
from pendant.sim import FakeClock, SimController

TOKEN = "right-token"
ANGLE_TOL_DEG = 1e-9
MOVE = {"angles": [10.0, -90.0, 0.0, -90.0, -90.0, 0.0]}


@pytest.fixture
def events() -> EventLog:
    return EventLog()


@pytest.fixture
def api(sim: SimController, events: EventLog) -> TestClient:
    return TestClient(create_app(sim, token=TOKEN, events=events))


def angles(sim: SimController) -> np.ndarray:
    return np.asarray(sim.get_pose().angles)


def test_a_command_without_the_token_is_401_and_nothing_moves(
    api: TestClient, sim: SimController, clock: FakeClock, events: EventLog
) -> None:
    before = angles(sim)
    response = api.put("/pose", params={"speed": 50}, json=MOVE)
    assert response.status_code == 401
    assert response.headers["content-type"].startswith("text/plain")
    assert TOKEN_HEADER in json.loads(response.text)
    clock.advance(10.0)
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)
    assert events.recent()[-1].kind is EventKind.REFUSED


def test_a_wrong_token_is_403_and_logged_with_the_client(
    api: TestClient, sim: SimController, events: EventLog
) -> None:
    response = api.put("/relax", headers={TOKEN_HEADER: "guess", "User-Agent": "curl/8.5"})
    assert response.status_code == 403
    assert "Wrong access token" in response.text
    event = events.recent()[-1]
    assert event.kind is EventKind.REFUSED
    assert "curl/8.5" in event.source and "PUT /relax" in event.message


def test_the_right_token_moves_the_arm_and_the_command_is_logged(
    api: TestClient, sim: SimController, clock: FakeClock, events: EventLog
) -> None:
    response = api.put("/pose", params={"speed": 50}, json=MOVE, headers={TOKEN_HEADER: TOKEN})
    assert response.status_code == 200
    clock.advance(30.0)
    np.testing.assert_allclose(angles(sim), MOVE["angles"], atol=1e-6)
    assert events.recent()[-1].kind is EventKind.COMMAND
    assert "PUT /pose -> 200" in events.recent()[-1].message


@pytest.mark.parametrize(
    "path", ["/pose", "/position", "/status/motion", "/status/motors", "/tool", "/signal/input/1"]
)
def test_reads_need_no_token(api: TestClient, path: str) -> None:
    assert api.get(path).status_code == 200


def test_simulator_routes_are_commands_too(api: TestClient) -> None:
    assert isinstance(api.app, FastAPI)
    paths = api.app.openapi()["paths"]
    sim_commands = [
        (method.upper(), path.replace("{port}", "1"))
        for path, operations in paths.items()
        if path.startswith("/sim")
        for method in operations
        if method in ("put", "post")
    ]
    assert sim_commands, "the simulator's routes are mounted"
    for method, path in sim_commands:
        assert api.request(method, path).status_code == 401, path


def test_without_a_token_the_api_is_open_as_before(sim: SimController) -> None:
    api = TestClient(create_app(sim))
    assert api.put("/freeze").status_code == 200
