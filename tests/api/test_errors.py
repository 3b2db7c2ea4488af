"""Every error the API answers: status, plain-text message, no 422, and a refused request changes nothing."""

from __future__ import annotations

import json
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.api import errors as api_errors
from pendant.controller.errors import (
    MSG_BAD_FORMAT,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
)
from tests.support.api_client import TEXT, arm_state

GOOD_POINT = {"x": 0.3, "y": 0.1, "z": 0.4}
GOOD_ROTATION = {"roll": 3.14, "pitch": 0, "yaw": 0}
GOOD_POSITION = {"point": GOOD_POINT, "rotation": GOOD_ROTATION}
GOOD_ANGLES = [0, -90, 90, 0, 90, 0]
ZERO_ROTATION = b'{"roll": 0, "pitch": 0, "yaw": 0}}'

BAD_POSITION_BODIES = {
    "not json": b"{",
    "empty": b"",
    "a list": b"[]",
    "no point": json.dumps({"rotation": GOOD_ROTATION}).encode(),
    "no rotation": json.dumps({"point": GOOD_POINT}).encode(),
    "no z": json.dumps({"point": {"x": 0, "y": 0}, "rotation": GOOD_ROTATION}).encode(),
    "no yaw": json.dumps({"point": GOOD_POINT, "rotation": {"roll": 0, "pitch": 0}}).encode(),
    "string number": json.dumps({"point": {**GOOD_POINT, "x": "0.3"}, "rotation": GOOD_ROTATION}).encode(),
    "boolean": json.dumps({"point": {**GOOD_POINT, "x": True}, "rotation": GOOD_ROTATION}).encode(),
    "null": json.dumps({"point": {**GOOD_POINT, "x": None}, "rotation": GOOD_ROTATION}).encode(),
    "NaN": b'{"point": {"x": NaN, "y": 0, "z": 0.4}, "rotation": ' + ZERO_ROTATION,
    "Infinity": b'{"point": {"x": 0, "y": 0, "z": 0.4}, "rotation": {"roll": Infinity, "pitch": 0, "yaw": 0}}',  # noqa: E501
    "-Infinity": b'{"point": {"x": -Infinity, "y": 0, "z": 0.4}, "rotation": ' + ZERO_ROTATION,
    "overflow": b'{"point": {"x": 1e400, "y": 0, "z": 0.4}, "rotation": ' + ZERO_ROTATION,
}
BAD_POSE_BODIES = {
    "not json": b"{angles",
    "empty": b"",
    "no angles": b"{}",
    "five angles": json.dumps({"angles": GOOD_ANGLES[:5]}).encode(),
    "seven angles": json.dumps({"angles": [*GOOD_ANGLES, 0]}).encode(),
    "string angle": json.dumps({"angles": ["0", -90, 90, 0, 90, 0]}).encode(),
    "boolean angle": json.dumps({"angles": [False, -90, 90, 0, 90, 0]}).encode(),
    "NaN": b'{"angles": [NaN, -90, 90, 0, 90, 0]}',
    "Infinity": b'{"angles": [0, -90, 90, 0, 90, Infinity]}',
    "angles not a list": b'{"angles": 5}',
}


def assert_error(response: Any, status: int, message: str) -> None:
    assert response.status_code == status, response.text
    assert response.headers["content-type"] == TEXT
    assert response.text == json.dumps(message)


@pytest.mark.parametrize("body", BAD_POSITION_BODIES.values(), ids=BAD_POSITION_BODIES.keys())
@pytest.mark.parametrize("method, path", [("PUT", "/position?speed=50"), ("POST", "/base")])
def test_a_malformed_position_is_400(client: TestClient, method: str, path: str, body: bytes) -> None:
    before = arm_state(client)
    assert_error(client.request(method, path, content=body), 400, MSG_BAD_FORMAT)
    assert arm_state(client) == before


@pytest.mark.parametrize("body", BAD_POSE_BODIES.values(), ids=BAD_POSE_BODIES.keys())
def test_a_malformed_pose_is_400(client: TestClient, body: bytes) -> None:
    before = arm_state(client)
    assert_error(client.put("/pose?speed=50", content=body), 400, MSG_BAD_FORMAT)
    assert arm_state(client) == before


@pytest.mark.parametrize(
    "path, body",
    [
        ("/poses/run", []),
        ("/positions/run", []),
        ("/poses/run", {"angles": GOOD_ANGLES}),
        ("/positions/run", GOOD_POSITION),
        ("/poses/run", [{"angles": GOOD_ANGLES}, {"angles": GOOD_ANGLES[:5]}]),
        ("/positions/run", [GOOD_POSITION, {"point": GOOD_POINT}]),
    ],
    ids=[
        "no poses",
        "no positions",
        "pose not in a list",
        "position not in a list",
        "bad 2nd pose",
        "bad 2nd",
    ],
)
def test_a_malformed_waypoint_list_is_400_and_nothing_moves(client: TestClient, path: str, body: Any) -> None:
    before = arm_state(client)
    assert_error(client.put(path, params={"speed": 50}, json=body), 400, MSG_BAD_FORMAT)
    assert arm_state(client) == before


@pytest.mark.parametrize(
    "tool",
    [
        {"point": GOOD_POINT, "rotation": GOOD_ROTATION, "radius": 0.1},
        {"name": "t", "rotation": GOOD_ROTATION, "radius": 0.1},
        {"name": "t", "point": GOOD_POINT, "rotation": GOOD_ROTATION},
        {"name": 5, "point": GOOD_POINT, "rotation": GOOD_ROTATION, "radius": 0.1},
        {"name": "t", "point": GOOD_POINT, "rotation": GOOD_ROTATION, "radius": -0.1},
    ],
    ids=["no name", "no point", "no radius", "name not a string", "negative radius"],
)
def test_a_malformed_tool_is_400(client: TestClient, tool: dict[str, Any]) -> None:
    before = arm_state(client)
    assert_error(client.post("/tool", json=tool), 400, MSG_BAD_FORMAT)
    assert arm_state(client) == before


MOTION_PATHS = ["/pose", "/poses/run", "/position", "/positions/run"]


def motion_body(path: str, client: TestClient) -> Any:
    current = client.get("/pose" if "pose" in path else "/position").json()
    return [current] if path.endswith("/run") else current


@pytest.mark.parametrize("path", MOTION_PATHS)
@pytest.mark.parametrize(
    "params, message",
    [
        ({"speed": 0}, api_errors.MSG_SPEED),
        ({"speed": -1}, api_errors.MSG_SPEED),
        ({"speed": 101}, api_errors.MSG_SPEED),
        ({"speed": "fast"}, api_errors.MSG_SPEED),
        ({"speed": "nan"}, api_errors.MSG_SPEED),
        ({"speed": "inf"}, api_errors.MSG_SPEED),
        ({"speed": ""}, api_errors.MSG_SPEED),
        ({"speed": 50, "type": "CIRCULAR"}, api_errors.MSG_TYPE),
        ({"speed": 50, "type": "linear"}, api_errors.MSG_TYPE),
        ({"speed": 50, "motionType": "ARC"}, api_errors.MSG_MOTION_TYPE),
        ({"speed": 50, "tcp_max_velocity": 0}, api_errors.MSG_TCP_MAX_VELOCITY),
        ({"speed": 50, "tcp_max_velocity": 2.5}, api_errors.MSG_TCP_MAX_VELOCITY),
        ({"speed": 50, "tcp_max_velocity": "-inf"}, api_errors.MSG_TCP_MAX_VELOCITY),
        ({"acceleration": 0}, api_errors.MSG_ACCELERATION),
        ({"tcp_max_velocity": -0.1}, api_errors.MSG_TCP_MAX_VELOCITY),
        ({"velocity": 0, "acceleration": 50}, api_errors.MSG_VELOCITY),
        ({"velocity": 50, "acceleration": 200.5}, api_errors.MSG_ACCELERATION),
    ],
)
def test_a_bad_motion_parameter_is_412_naming_it(
    client: TestClient, path: str, params: dict[str, Any], message: str
) -> None:
    body = motion_body(path, client)
    before = arm_state(client)
    assert_error(client.put(path, params=params, json=body), 412, message)
    assert arm_state(client) == before


def test_parameter_messages_name_the_range() -> None:
    assert "speed" in api_errors.MSG_SPEED and "above 0, up to 100" in api_errors.MSG_SPEED
    assert "up to 200" in api_errors.MSG_ACCELERATION
    assert (
        "tcp_max_velocity" in api_errors.MSG_TCP_MAX_VELOCITY
        and "above 0, up to 2" in api_errors.MSG_TCP_MAX_VELOCITY
    )
    assert "JOINT or LINEAR" in api_errors.MSG_TYPE


@pytest.mark.parametrize("port", ["0", "3", "-1", "abc", "1.5"])
@pytest.mark.parametrize("method, suffix", [("GET", ""), ("PUT", "/high"), ("PUT", "/low")])
def test_a_bad_output_port_is_412(client: TestClient, method: str, suffix: str, port: str) -> None:
    before = arm_state(client)
    assert_error(client.request(method, f"/signal/output/{port}{suffix}"), 412, api_errors.MSG_OUTPUT_PORT)
    assert arm_state(client) == before


@pytest.mark.parametrize("port", ["0", "5", "x"])
def test_a_bad_input_port_is_412(client: TestClient, port: str) -> None:
    assert_error(client.get(f"/signal/input/{port}"), 412, api_errors.MSG_INPUT_PORT)


@pytest.mark.parametrize("timeout", ["-1", "soon", "1e99", str(2**31)])
@pytest.mark.parametrize("command", ["open", "close"])
def test_a_bad_gripper_timeout_is_412(client: TestClient, command: str, timeout: str) -> None:
    assert_error(client.put(f"/gripper/{command}", params={"timeout": timeout}), 412, api_errors.MSG_TIMEOUT)


def test_an_unreachable_position_is_412(client: TestClient) -> None:
    far = {"point": {"x": 5.0, "y": 0.0, "z": 0.3}, "rotation": GOOD_ROTATION}
    before = arm_state(client)
    for path, body in (("/position", far), ("/positions/run", [far])):
        assert_error(client.put(path, params={"speed": 50}, json=body), 412, MSG_UNREACHABLE_POSITION)
    assert arm_state(client) == before


def test_a_pose_beyond_the_joint_limits_is_412(client: TestClient) -> None:
    beyond = {"angles": [0, -90, 90, 0, 90, 100_000]}
    before = arm_state(client)
    for path, body in (("/pose", beyond), ("/poses/run", [beyond])):
        assert_error(client.put(path, params={"speed": 50}, json=body), 412, MSG_UNREACHABLE_POSE)
    assert arm_state(client) == before


EVERY_PULSE_CALL = [
    ("GET", "/position", None),
    ("GET", "/pose", None),
    ("GET", "/status/motion", None),
    ("GET", "/status/motors", None),
    ("GET", "/tool", None),
    ("GET", "/base", None),
    ("GET", "/robot/id", None),
    ("GET", "/signal/output/1", None),
    ("GET", "/signal/input/1", None),
    ("PUT", "/position?speed=10", GOOD_POSITION),
    ("PUT", "/pose?speed=10", {"angles": GOOD_ANGLES}),
    ("PUT", "/positions/run?speed=10", [GOOD_POSITION]),
    ("PUT", "/poses/run?speed=10", [{"angles": GOOD_ANGLES}]),
    ("PUT", "/gripper/open", None),
    ("PUT", "/gripper/close", None),
    ("PUT", "/relax", None),
    ("PUT", "/freeze", None),
    ("PUT", "/signal/output/1/high", None),
    ("PUT", "/signal/output/1/low", None),
    ("PUT", "/pack", None),
    ("POST", "/base", GOOD_POSITION),
    (
        "POST",
        "/tool",
        {"name": "t", "point": GOOD_POINT, "rotation": GOOD_ROTATION, "radius": 0.1},
    ),
]


@pytest.mark.parametrize("method, path, body", EVERY_PULSE_CALL)
def test_a_silent_robot_answers_500_everywhere(
    client: TestClient, sim: Any, method: str, path: str, body: Any
) -> None:
    from pendant.sim import Fault

    sim.inject_fault(Fault.NO_RESPONSE)
    assert_error(client.request(method, path, json=body), 500, MSG_NOT_RESPONDING)


@pytest.mark.parametrize("method, path, body", EVERY_PULSE_CALL)
def test_an_emergency_answers_503_everywhere(
    client: TestClient, sim: Any, method: str, path: str, body: Any
) -> None:
    from pendant.sim import Fault

    sim.inject_fault(Fault.EMERGENCY)
    assert_error(client.request(method, path, json=body), 503, MSG_EMERGENCY)


MALFORMED_CALLS = [
    ("PUT", "/pose?speed=10", None),  # no body
    ("PUT", "/pose?speed=500", {"angles": GOOD_ANGLES}),  # speed out of range
    ("PUT", "/position", GOOD_POSITION),  # no speed
    ("POST", "/base", {"point": GOOD_POINT}),  # no rotation
    ("GET", "/signal/output/9", None),  # no such port
]


@pytest.mark.parametrize("method, path, body", MALFORMED_CALLS)
def test_a_faulted_robot_answers_its_fault_even_to_a_malformed_request(
    client: TestClient, sim: Any, method: str, path: str, body: Any
) -> None:
    from pendant.sim import Fault

    sim.inject_fault(Fault.EMERGENCY)
    assert_error(client.request(method, path, json=body), 503, MSG_EMERGENCY)
    sim.reset()
    sim.inject_fault(Fault.NO_RESPONSE)
    assert_error(client.request(method, path, json=body), 500, MSG_NOT_RESPONDING)


def test_unknown_paths_and_methods_answer_in_plain_text(client: TestClient) -> None:
    assert_error(client.get("/no/such/thing"), 404, "Not Found")
    response = client.delete("/pose")
    assert_error(response, 405, "Method Not Allowed")
    assert "GET" in response.headers["allow"]


@pytest.mark.parametrize(
    "method, path, body",
    [
        ("PUT", "/pose?speed=x&type=y&tcp_max_velocity=z", b"nope"),
        ("PUT", "/position", b"{}"),
        ("GET", "/signal/output/one", None),
        ("PUT", "/gripper/open?timeout=a", None),
        ("POST", "/tool", b"[1, 2]"),
        ("PUT", "/poses/run?speed=1e999", b"[{}]"),
    ],
)
def test_fastapi_422_never_appears(client: TestClient, method: str, path: str, body: bytes | None) -> None:
    response = client.request(method, path, content=body)
    assert response.status_code in (400, 412)
    assert response.headers["content-type"] == TEXT


def test_parameters_are_checked_before_the_body(client: TestClient) -> None:
    assert_error(client.put("/pose", params={"speed": 0}, content=b"{"), 412, api_errors.MSG_SPEED)
