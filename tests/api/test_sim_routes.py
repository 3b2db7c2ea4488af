"""The simulator-only routes under /sim: inputs, a hand on the relaxed arm, faults, reset."""

from __future__ import annotations

import json

import httpx
import pytest
from fastapi.testclient import TestClient

from pendant.api import errors as api_errors
from pendant.controller.errors import MSG_EMERGENCY, MSG_NOT_RESPONDING
from tests.support.api_client import TEXT, angles_close


def assert_empty_ok(response: httpx.Response) -> None:
    assert response.status_code == 200, response.text
    assert response.content == b""


@pytest.mark.parametrize("port", [1, 2, 3, 4])
def test_inputs_follow_the_simulated_world(client: TestClient, port: int) -> None:
    assert_empty_ok(client.put(f"/sim/signal/input/{port}/high"))
    assert client.get(f"/signal/input/{port}").json() == "HIGH"
    assert_empty_ok(client.put(f"/sim/signal/input/{port}/low"))
    assert client.get(f"/signal/input/{port}").json() == "LOW"


@pytest.mark.parametrize("port", ["0", "5", "x"])
def test_a_bad_simulated_input_port_is_412(client: TestClient, port: str) -> None:
    response = client.put(f"/sim/signal/input/{port}/high")
    assert response.status_code == 412
    assert response.text == json.dumps(api_errors.MSG_INPUT_PORT)


def test_a_hand_moves_the_arm_only_when_relaxed(client: TestClient) -> None:
    angles = client.get("/pose").json()["angles"]
    moved = [angles[0] + 15.0, *angles[1:]]
    refused = client.put("/sim/pose", json={"angles": moved})
    assert refused.status_code == 412
    assert refused.headers["content-type"] == TEXT
    assert angles_close(client.get("/pose").json()["angles"], angles)

    client.put("/relax")
    assert_empty_ok(client.put("/sim/pose", json={"angles": moved}))
    assert angles_close(client.get("/pose").json()["angles"], moved)


def test_a_hand_cannot_put_the_arm_inside_an_obstacle(client: TestClient) -> None:
    """The test hook refuses what the arm could never reach, rather than leave a CI run with an arm stuck
    inside the cell, every later move refused for reasons nobody set up."""
    home = client.get("/pose").json()["angles"]
    # A 12 cm box around where the flange passes when joint 1 turns 45° from home.
    wall = {
        "obstacleType": "BOX",
        "name": "wall",
        "sides": {"x": 0.12, "y": 0.12, "z": 0.12},
        "centerPosition": {
            "point": {"x": -0.2444, "y": -0.4148, "z": 0.4849},
            "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
        },
    }
    assert client.put("/environment", json=wall).status_code == 200
    client.put("/relax")
    inside = [home[0] + 45.0, *home[1:]]
    refused = client.put("/sim/pose", json={"angles": inside})
    assert refused.status_code == 412
    assert refused.json() == "Collision detected: at that pose the arm or its tool would be inside 'wall'"
    assert angles_close(client.get("/pose").json()["angles"], home)  # the arm stayed

    clear = [home[0] - 45.0, *home[1:]]  # the other way: nothing there
    assert_empty_ok(client.put("/sim/pose", json={"angles": clear}))
    assert angles_close(client.get("/pose").json()["angles"], clear)


def test_a_hand_pose_must_be_a_pose(client: TestClient) -> None:
    client.put("/relax")
    assert client.put("/sim/pose", json={"angles": [0, 1]}).status_code == 400


def test_an_injected_error_is_recovered_by_recover(client: TestClient) -> None:
    assert_empty_ok(client.put("/sim/fault/error"))
    assert client.get("/status/motion").json() == "ERROR"
    assert client.put("/recover").json() == "SUCCESS"
    assert client.get("/status/motion").json() == "IDLE"


def test_an_injected_emergency_lasts_until_reset(client: TestClient) -> None:
    assert_empty_ok(client.put("/sim/fault/emergency"))
    assert client.get("/pose").text == json.dumps(MSG_EMERGENCY)
    assert client.put("/recover").status_code == 503
    assert_empty_ok(client.put("/sim/reset"))
    assert client.get("/status/motion").json() == "IDLE"


def test_an_injected_silence_lasts_until_reset(client: TestClient) -> None:
    assert_empty_ok(client.put("/sim/fault/no_response"))
    response = client.get("/robot/id")
    assert (response.status_code, response.text) == (500, json.dumps(MSG_NOT_RESPONDING))
    assert_empty_ok(client.put("/sim/reset"))
    assert client.get("/robot/id").status_code == 200


def test_an_unknown_fault_is_412(client: TestClient) -> None:
    response = client.put("/sim/fault/meteor")
    assert (response.status_code, response.text) == (412, json.dumps(api_errors.MSG_FAULT))


def test_reset_brings_back_the_start(client: TestClient) -> None:
    start = {path: client.get(path).text for path in ("/pose", "/tool", "/base", "/signal/output/1")}
    client.put("/signal/output/1/high")
    client.post(
        "/base", json={"point": {"x": 0.1, "y": 0, "z": 0}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0}}
    )
    client.put("/relax")
    client.put("/sim/signal/input/1/high")
    assert_empty_ok(client.put("/sim/reset"))
    assert {path: client.get(path).text for path in start} == start
    assert client.get("/signal/input/1").json() == "LOW"
    assert client.get("/status/motion").json() == "IDLE"


def test_reset_keeping_the_cell_clears_only_the_fault(client: TestClient) -> None:
    """What the banner's "Reset simulator (keeps the cell)" sends after an emergency: the arm stays where it
    stopped, the obstacles stay; a plain reset still empties the cell."""
    box = {
        "obstacleType": "BOX",
        "name": "fixture",
        "sides": {"x": 0.1, "y": 0.1, "z": 0.1},
        "centerPosition": {
            "point": {"x": 0.5, "y": -0.4, "z": 0.1},
            "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
        },
    }
    assert client.put("/environment", json=box).status_code == 200
    home = client.get("/pose").json()["angles"]
    moved = [home[0] + 20.0, *home[1:]]
    client.put("/relax")
    assert_empty_ok(client.put("/sim/pose", json={"angles": moved}))
    client.put("/sim/fault/emergency")
    assert_empty_ok(client.put("/sim/reset", params={"keep_cell": "true"}))
    assert client.get("/status/motion").json() == "IDLE"
    assert [o["name"] for o in client.get("/environment").json()] == ["fixture"]
    assert angles_close(client.get("/pose").json()["angles"], moved)
    assert client.get("/status/failure").json() == []

    assert_empty_ok(client.put("/sim/reset"))
    assert client.get("/environment").json() == []
    assert angles_close(client.get("/pose").json()["angles"], home)
