"""`pendant --no-ui` over real HTTP on 127.0.0.1: every PULSE API endpoint, and its errors, on the wire.

One process serves the whole module; each test starts from PUT /sim/reset. The server runs on the real clock:
one test waits for a motion to end (polling /status/motion, bounded), the others stop theirs with /freeze.
About 90 requests in all.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Iterator
from datetime import datetime
from typing import Any

import httpx
import pytest

from pendant.api import errors as api_errors
from pendant.controller.errors import (
    MSG_BAD_FORMAT,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
)
from pendant.controller.types import MotorStatus, Pose, Position, Tool
from tests.support.api_client import JSON, TEXT, angles_close
from tests.support.launchers import running_pendant
from tests.support.waiting import SAFETY_NET_S

MOTION_DEADLINE_S = SAFETY_NET_S  # a short move at full speed ends well within this
POLL_INTERVAL_S = 0.1
CLIENT_TIMEOUT_S = 30.0  # a safety net: the pendant runs at nice 19 beside the timed tests
FAR_POSITION = {"point": {"x": 5.0, "y": 0.0, "z": 0.3}, "rotation": {"roll": 3.14, "pitch": 0, "yaw": 0}}
BEYOND_LIMITS = {"angles": [0, -90, 90, 0, 90, 100_000]}
TOOL = {
    "name": "gripper",
    "point": {"x": 0, "y": 0, "z": 0.1},
    "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
    "radius": 0.05,
}
BASE = {"point": {"x": 0.1, "y": -0.2, "z": 0.05}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0.5}}


@pytest.fixture(scope="module")
def base_url() -> Iterator[str]:
    with running_pendant("--model", "pulse75") as url:
        yield url


@pytest.fixture
def http(base_url: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=base_url, timeout=CLIENT_TIMEOUT_S) as client:
        assert client.put("/sim/reset").status_code == 200
        yield client


def wait_until_idle(http: httpx.Client) -> str:
    """The motion status once the arm stops, or RUNNING if it is still moving at the deadline."""
    deadline = time.monotonic() + MOTION_DEADLINE_S
    status = http.get("/status/motion").json()
    while status == "RUNNING" and time.monotonic() < deadline:
        time.sleep(POLL_INTERVAL_S)  # a real process on the real clock: no fake clock reaches it
        status = http.get("/status/motion").json()
    return status


def nudged_angles(http: httpx.Client, *deltas: float) -> list[float]:
    angles = http.get("/pose").json()["angles"]
    return [angle + delta for angle, delta in zip(angles, (*deltas, 0, 0, 0, 0, 0, 0), strict=False)]


def nudged_position(position: dict[str, Any], dz: float) -> dict[str, Any]:
    return {**position, "point": {**position["point"], "z": position["point"]["z"] + dz}}


def assert_empty_ok(response: httpx.Response) -> None:
    assert response.status_code == 200, f"{response.request.url}: {response.text}"
    assert response.headers["content-type"] == TEXT
    assert response.content == b""


def assert_text(response: httpx.Response, word: str) -> None:
    assert response.status_code == 200, f"{response.request.url}: {response.text}"
    assert response.headers["content-type"] == TEXT
    assert response.text == json.dumps(word)


def assert_json(response: httpx.Response) -> Any:
    assert response.status_code == 200, f"{response.request.url}: {response.text}"
    assert response.headers["content-type"] == JSON
    return response.json()


def assert_error(response: httpx.Response, status: int, message: str) -> None:
    assert response.status_code == status, f"{response.request.url}: {response.text}"
    assert response.headers["content-type"] == TEXT
    assert response.text == json.dumps(message)


# Reads


def check_pose(body: Any) -> None:
    assert set(body) == {"angles", "timestamp"}  # SDK >= 1.8 reads the time of the reading
    assert len(Pose.model_validate(body).angles) == 6
    datetime.fromisoformat(body["timestamp"])


def check_position(body: Any) -> None:
    assert set(body) == {"point", "rotation", "timestamp"}
    Position.model_validate(body)
    datetime.fromisoformat(body["timestamp"])


def check_base(body: Any) -> None:
    assert set(body) == {"point", "rotation"}
    Position.model_validate(body)


def check_tool(body: Any) -> None:
    assert set(body) == {"name", "point", "rotation", "radius"}
    Tool.model_validate(body)


def check_motors(body: Any) -> None:
    assert len(body) == 6
    for motor in body:
        assert set(motor) == set(MotorStatus.model_fields)
        MotorStatus.model_validate(motor)


JSON_READS: dict[str, Callable[[Any], None]] = {
    "/pose": check_pose,
    "/position": check_position,
    "/tool": check_tool,
    "/base": check_base,
    "/status/motors": check_motors,
}
TEXT_READS = {
    "/status/motion": "IDLE",
    "/signal/output/1": "LOW",
    "/signal/output/2": "LOW",
    "/signal/input/1": "LOW",
    "/signal/input/4": "LOW",
}


def test_every_read_answers_in_the_references_shape(http: httpx.Client) -> None:
    for path, check in JSON_READS.items():
        check(assert_json(http.get(path)))
    for path, word in TEXT_READS.items():
        assert_text(http.get(path), word)
    robot_id = http.get("/robot/id")
    assert robot_id.status_code == 200
    assert robot_id.headers["content-type"] == TEXT
    assert isinstance(robot_id.json(), str) and robot_id.json()
    assert http.get("/robot/id").text == robot_id.text  # stable


# Commands


def test_a_motion_over_real_http_reaches_its_target(http: httpx.Client) -> None:
    target = nudged_angles(http, 10.0, 5.0)
    # Speed 20: about 2 s, so the arm is still moving when a loaded machine asks (at 100 it takes 0.37 s).
    assert_empty_ok(http.put("/pose", params={"speed": 20}, json={"angles": target}))
    assert http.get("/status/motion").json() == "RUNNING"
    assert wait_until_idle(http) == "IDLE"
    assert angles_close(http.get("/pose").json()["angles"], target)


def test_every_motion_command_is_accepted_and_freeze_stops_them_all(http: httpx.Client) -> None:
    start = http.get("/position").json()
    angles = nudged_angles(http, 5.0)
    moved = assert_json(
        http.put("/position", params={"speed": 50, "type": "LINEAR"}, json=nudged_position(start, -0.01))
    )
    check_base(moved)  # PUT /position answers the position alone, as the reference prints it
    assert_empty_ok(http.put("/pose", params={"speed": 50}, json={"angles": angles}))
    waypoints = [{"angles": angles}, {"angles": [angles[0] + 5.0, *angles[1:]]}]
    assert_empty_ok(http.put("/poses/run", params={"speed": 50}, json=waypoints))
    positions = [nudged_position(start, -0.01), nudged_position(start, -0.02)]
    assert_empty_ok(http.put("/positions/run", params={"speed": 50, "type": "LINEAR"}, json=positions))
    assert_empty_ok(http.put("/gripper/open", params={"timeout": 100}))
    assert_empty_ok(http.put("/gripper/close"))
    assert_empty_ok(http.put("/pack"))
    assert http.get("/status/motion").json() == "RUNNING"
    assert_empty_ok(http.put("/freeze"))
    assert_text(http.get("/status/motion"), "IDLE")


def test_relax_gives_zero_gravity_until_freeze(http: httpx.Client) -> None:
    assert_empty_ok(http.put("/relax"))
    assert_text(http.get("/status/motion"), "ZERO_GRAVITY")
    assert_empty_ok(http.put("/freeze"))
    assert_text(http.get("/status/motion"), "IDLE")


def test_outputs_keep_their_level_and_inputs_follow_the_simulator(http: httpx.Client) -> None:
    assert_empty_ok(http.put("/signal/output/2/high"))
    assert_text(http.get("/signal/output/2"), "HIGH")
    assert_empty_ok(http.put("/signal/output/2/low"))
    assert_text(http.get("/signal/output/2"), "LOW")
    assert_empty_ok(http.put("/sim/signal/input/3/high"))
    assert_text(http.get("/signal/input/3"), "HIGH")


def test_post_tool_and_base_answer_with_what_they_set(http: httpx.Client) -> None:
    assert Tool.model_validate(assert_json(http.post("/tool", json=TOOL))) == Tool.model_validate(TOOL)
    assert Tool.model_validate(assert_json(http.get("/tool"))) == Tool.model_validate(TOOL)
    assert Position.model_validate(assert_json(http.post("/base", json=BASE))) == Position.model_validate(
        BASE
    )
    assert Position.model_validate(assert_json(http.get("/base"))) == Position.model_validate(BASE)


def test_recover_after_an_error_answers_success(http: httpx.Client) -> None:
    assert_empty_ok(http.put("/sim/fault/error"))
    assert_text(http.get("/status/motion"), "ERROR")
    assert_text(http.put("/recover"), "SUCCESS")
    assert_text(http.get("/status/motion"), "IDLE")


# Errors


def test_a_malformed_body_is_400(http: httpx.Client) -> None:
    assert_error(http.put("/pose", params={"speed": 10}, json={"angles": [0, 0]}), 400, MSG_BAD_FORMAT)
    unparsable = http.put(
        "/position", params={"speed": 10}, content=b"{", headers={"content-type": "application/json"}
    )
    assert_error(unparsable, 400, MSG_BAD_FORMAT)
    assert_error(http.post("/tool", json={"name": "no point"}), 400, MSG_BAD_FORMAT)


def test_unreachable_targets_and_bad_speeds_are_412_and_nothing_moves(http: httpx.Client) -> None:
    before = http.get("/pose").json()["angles"]
    good = {"angles": before}
    far = http.put("/position", params={"speed": 50}, json=FAR_POSITION)
    assert_error(far, 412, MSG_UNREACHABLE_POSITION)
    assert_error(http.put("/pose", params={"speed": 50}, json=BEYOND_LIMITS), 412, MSG_UNREACHABLE_POSE)
    assert_error(http.put("/pose", params={"speed": 500}, json=good), 412, api_errors.MSG_SPEED)
    assert_error(http.put("/pose", params={"speed": 0}, json=good), 412, api_errors.MSG_SPEED)
    assert http.get("/pose").json()["angles"] == before


def test_a_robot_that_does_not_respond_is_500_until_reset(http: httpx.Client) -> None:
    assert_empty_ok(http.put("/sim/fault/no_response"))
    assert_error(http.get("/pose"), 500, MSG_NOT_RESPONDING)
    assert_error(http.put("/relax"), 500, MSG_NOT_RESPONDING)
    assert_empty_ok(http.put("/sim/reset"))
    check_pose(assert_json(http.get("/pose")))


def test_an_emergency_is_503_even_to_recover_until_reset(http: httpx.Client) -> None:
    assert_empty_ok(http.put("/sim/fault/emergency"))
    assert_error(http.get("/status/motion"), 503, MSG_EMERGENCY)
    assert_error(http.put("/freeze"), 503, MSG_EMERGENCY)
    assert_error(http.put("/recover"), 503, MSG_EMERGENCY)
    assert_empty_ok(http.put("/sim/reset"))
    assert_text(http.get("/status/motion"), "IDLE")


def test_the_docs_are_served(http: httpx.Client) -> None:
    assert http.get("/openapi.json").json()["info"]["title"] == "PULSE REST API"
    assert http.get("/docs").status_code == 200
