"""Every GET endpoint: status 200, the reference's content type, and a body that says what the arm says."""

from __future__ import annotations

import json
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.controller.types import MotionStatus, MotorStatus, Pose, Position, SignalLevel, Tool
from tests.support.api_client import JSON, TEXT

MOTOR_FIELDS = set(MotorStatus.model_fields)


def test_get_pose_is_the_six_joint_angles_in_degrees(client: TestClient, sim: Any) -> None:
    response = client.get("/pose")
    assert response.status_code == 200
    assert response.headers["content-type"] == JSON
    assert Pose.model_validate_json(response.content) == sim.get_pose()
    assert len(response.json()["angles"]) == 6


def test_get_position_is_the_tcp_point_and_rotation(client: TestClient, sim: Any) -> None:
    response = client.get("/position")
    assert response.status_code == 200
    assert response.headers["content-type"] == JSON
    body = response.json()
    assert set(body) == {"point", "rotation", "timestamp"}
    assert set(body["point"]) == {"x", "y", "z"}
    assert set(body["rotation"]) == {"roll", "pitch", "yaw"}
    assert Position.model_validate(body) == sim.get_position()


def test_get_tool_names_the_tool_its_tcp_and_radius(client: TestClient, sim: Any) -> None:
    response = client.get("/tool")
    assert response.status_code == 200
    assert response.headers["content-type"] == JSON
    assert set(response.json()) == {"name", "point", "rotation", "radius"}
    assert Tool.model_validate(response.json()) == sim.get_tool()


def test_get_base_is_a_position(client: TestClient, sim: Any) -> None:
    response = client.get("/base")
    assert response.status_code == 200
    assert response.headers["content-type"] == JSON
    assert Position.model_validate(response.json()) == sim.get_base()


def test_get_motion_status_is_a_quoted_word_in_plain_text(client: TestClient) -> None:
    response = client.get("/status/motion")
    assert response.status_code == 200
    assert response.headers["content-type"] == TEXT
    assert response.text == '"IDLE"'
    assert json.loads(response.text) in {status.value for status in MotionStatus}


def test_get_motors_lists_six_servos_with_every_telemetry_field(client: TestClient) -> None:
    response = client.get("/status/motors")
    assert response.status_code == 200
    assert response.headers["content-type"] == JSON
    motors = response.json()
    assert len(motors) == 6
    for motor in motors:
        assert set(motor) == MOTOR_FIELDS
        assert all(isinstance(value, float | int) for value in motor.values())


def test_motor_angles_are_the_pose_angles(client: TestClient) -> None:
    angles = client.get("/pose").json()["angles"]
    motor_angles = [motor["angle"] for motor in client.get("/status/motors").json()]
    assert motor_angles == pytest.approx(angles, abs=1e-6)


def test_get_robot_id_is_a_quoted_string(client: TestClient, sim: Any) -> None:
    response = client.get("/robot/id")
    assert response.status_code == 200
    assert response.headers["content-type"] == TEXT
    assert response.text == json.dumps(sim.get_robot_id())
    assert sim.get_robot_id()


@pytest.mark.parametrize("port", [1, 2])
def test_get_output_is_low_at_start(client: TestClient, port: int) -> None:
    response = client.get(f"/signal/output/{port}")
    assert response.status_code == 200
    assert response.headers["content-type"] == TEXT
    assert response.text == '"LOW"'


@pytest.mark.parametrize("port", [1, 2, 3, 4])
def test_get_input_reads_what_the_world_sets(client: TestClient, sim: Any, port: int) -> None:
    assert client.get(f"/signal/input/{port}").text == '"LOW"'
    sim.set_input(port, SignalLevel.HIGH)
    response = client.get(f"/signal/input/{port}")
    assert response.status_code == 200
    assert response.headers["content-type"] == TEXT
    assert response.text == '"HIGH"'
