"""Every PUT/POST command: its answer, and the change a user then sees on the arm."""

from __future__ import annotations

import json
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.controller.types import Position, SignalLevel, Tool
from tests.support.api_client import JSON, POS_TOL_M, TEXT, angles_close, finish_motion


def nudged_pose(client: TestClient, *deltas: float) -> list[float]:
    angles = client.get("/pose").json()["angles"]
    return [angle + delta for angle, delta in zip(angles, (*deltas, 0, 0, 0, 0, 0, 0), strict=False)]


def nudged_position(client: TestClient, dz: float) -> dict[str, Any]:
    position = client.get("/position").json()
    position["point"]["z"] += dz
    return position


def assert_empty_ok(response: Any) -> None:
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == TEXT
    assert response.content == b""


def point_distance(a: dict[str, Any], b: dict[str, Any]) -> float:
    return max(abs(a["point"][axis] - b["point"][axis]) for axis in "xyz")


def test_put_pose_moves_the_arm_there(client: TestClient, clock: Any) -> None:
    target = nudged_pose(client, 10.0, -5.0)
    response = client.put("/pose", params={"speed": 50}, json={"angles": target})
    assert_empty_ok(response)
    assert finish_motion(client, clock) == "IDLE"
    assert angles_close(client.get("/pose").json()["angles"], target)


def test_put_pose_accepts_integer_angles(client: TestClient, clock: Any) -> None:
    target = [round(angle) for angle in nudged_pose(client, 10.0)]
    assert_empty_ok(client.put("/pose?speed=100", json={"angles": target}))
    finish_motion(client, clock)
    assert angles_close(client.get("/pose").json()["angles"], [float(angle) for angle in target])


def test_put_pose_reports_running_until_the_clock_has_moved_the_arm(client: TestClient, clock: Any) -> None:
    target = nudged_pose(client, 20.0)
    client.put("/pose", params={"speed": 10}, json={"angles": target})
    assert client.get("/status/motion").json() == "RUNNING"
    assert finish_motion(client, clock) == "IDLE"


def test_put_position_answers_with_a_position_and_moves_the_tcp(client: TestClient, clock: Any) -> None:
    target = nudged_position(client, -0.02)
    response = client.put("/position", params={"speed": 30, "type": "LINEAR"}, json=target)
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == JSON
    Position.model_validate(response.json())
    assert finish_motion(client, clock) == "IDLE"
    assert point_distance(client.get("/position").json(), target) <= POS_TOL_M


def test_run_poses_goes_through_the_waypoints_to_the_last(client: TestClient, clock: Any) -> None:
    first, last = nudged_pose(client, 5.0), nudged_pose(client, 10.0, 5.0)
    response = client.put("/poses/run", params={"speed": 60}, json=[{"angles": first}, {"angles": last}])
    assert_empty_ok(response)
    assert finish_motion(client, clock) == "IDLE"
    assert angles_close(client.get("/pose").json()["angles"], last)


def test_run_positions_goes_through_the_waypoints_to_the_last(client: TestClient, clock: Any) -> None:
    first, last = nudged_position(client, -0.01), nudged_position(client, -0.03)
    response = client.put("/positions/run", params={"speed": 60, "type": "LINEAR"}, json=[first, last])
    assert_empty_ok(response)
    assert finish_motion(client, clock) == "IDLE"
    assert point_distance(client.get("/position").json(), last) <= POS_TOL_M


@pytest.mark.parametrize("command", ["open", "close"])
def test_gripper_commands_answer_empty(client: TestClient, command: str) -> None:
    assert_empty_ok(client.put(f"/gripper/{command}"))
    assert_empty_ok(client.put(f"/gripper/{command}", params={"timeout": 1000}))


def test_relax_gives_zero_gravity_and_freeze_holds(client: TestClient) -> None:
    assert_empty_ok(client.put("/relax"))
    assert client.get("/status/motion").json() == "ZERO_GRAVITY"
    assert_empty_ok(client.put("/freeze"))
    assert client.get("/status/motion").json() != "ZERO_GRAVITY"


@pytest.mark.parametrize("port", [1, 2])
def test_outputs_follow_high_and_low(client: TestClient, port: int) -> None:
    assert_empty_ok(client.put(f"/signal/output/{port}/high"))
    assert client.get(f"/signal/output/{port}").text == '"HIGH"'
    other = 3 - port
    assert client.get(f"/signal/output/{other}").text == '"LOW"'
    assert_empty_ok(client.put(f"/signal/output/{port}/low"))
    assert client.get(f"/signal/output/{port}").text == '"LOW"'


def test_recover_after_an_error_answers_success_and_idle(client: TestClient, sim: Any) -> None:
    from pendant.sim import Fault

    sim.inject_fault(Fault.ERROR)
    assert client.get("/status/motion").json() == "ERROR"
    response = client.put("/recover")
    assert response.status_code == 200
    assert response.headers["content-type"] == TEXT
    assert response.text == '"SUCCESS"'
    assert client.get("/status/motion").json() == "IDLE"


def test_pack_moves_the_arm_to_its_transport_pose(client: TestClient, clock: Any) -> None:
    before = client.get("/pose").json()["angles"]
    assert_empty_ok(client.put("/pack"))
    finish_motion(client, clock)
    assert not angles_close(client.get("/pose").json()["angles"], before)


def test_post_tool_sets_the_tool_and_answers_with_it(client: TestClient) -> None:
    tool = {
        "name": "gripper",
        "point": {"x": 0, "y": 0, "z": 0.1},
        "rotation": {"roll": 0, "pitch": 0, "yaw": 0},
        "radius": 0.05,
    }
    response = client.post("/tool", json=tool)
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == JSON
    assert Tool.model_validate(response.json()) == Tool.model_validate(tool)
    assert Tool.model_validate(client.get("/tool").json()) == Tool.model_validate(tool)


def test_post_base_sets_the_zero_point_and_answers_with_it(client: TestClient) -> None:
    base = {"point": {"x": 0.1, "y": -0.2, "z": 0.05}, "rotation": {"roll": 0, "pitch": 0, "yaw": 0.5}}
    response = client.post("/base", json=base)
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == JSON
    assert Position.model_validate(response.json()) == Position.model_validate(base)
    assert Position.model_validate(client.get("/base").json()) == Position.model_validate(base)


def test_a_body_sent_as_form_data_by_curl_is_read_as_json(client: TestClient, clock: Any) -> None:
    target = nudged_pose(client, 10.0)
    response = client.put(
        "/pose?speed=50",
        content=json.dumps({"angles": target}),
        headers={"content-type": "application/x-www-form-urlencoded"},
    )
    assert_empty_ok(response)
    finish_motion(client, clock)
    assert angles_close(client.get("/pose").json()["angles"], target)


def test_set_input_from_the_simulator_changes_what_the_api_reads(client: TestClient, sim: Any) -> None:
    sim.set_input(3, SignalLevel.HIGH)
    assert client.get("/signal/input/3").json() == "HIGH"
