"""Rozum's later SDK parameters (`motionType`, `velocity`, `acceleration`) reach the controller right."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller.types import MotionParams, MotionType
from tests.support.api_client import RecordingController


@pytest.fixture
def spy(sim: Any) -> RecordingController:
    return RecordingController(sim)


@pytest.fixture
def spied(spy: RecordingController) -> Iterator[TestClient]:
    with TestClient(create_app(spy)) as test_client:
        yield test_client


def sent_params(client: TestClient, spy: RecordingController, query: str) -> MotionParams:
    pose = client.get("/pose").json()
    response = client.put(f"/pose?{query}", json=pose)
    assert response.status_code == 200, response.text
    return spy.motion_params[-1]


def test_speed_alone_means_joint_motion_at_full_tcp_velocity(
    spied: TestClient, spy: RecordingController
) -> None:
    params = sent_params(spied, spy, "speed=40")
    assert params == MotionParams(speed=40, motion_type=MotionType.JOINT, tcp_max_velocity=2.0)


def test_type_and_tcp_max_velocity_pass_through(spied: TestClient, spy: RecordingController) -> None:
    params = sent_params(spied, spy, "speed=40&type=LINEAR&tcp_max_velocity=0.25")
    assert (params.motion_type, params.tcp_max_velocity) == (MotionType.LINEAR, 0.25)


def test_motion_type_is_an_alias_of_type(spied: TestClient, spy: RecordingController) -> None:
    assert sent_params(spied, spy, "speed=40&motionType=LINEAR").motion_type == MotionType.LINEAR


def test_type_wins_over_motion_type(spied: TestClient, spy: RecordingController) -> None:
    params = sent_params(spied, spy, "speed=40&type=JOINT&motionType=LINEAR")
    assert params.motion_type == MotionType.JOINT


def test_velocity_and_acceleration_stand_in_for_speed(spied: TestClient, spy: RecordingController) -> None:
    params = sent_params(spied, spy, "velocity=30&acceleration=60")
    assert (params.speed, params.acceleration) == (30, 60)


def test_speed_wins_over_velocity(spied: TestClient, spy: RecordingController) -> None:
    params = sent_params(spied, spy, "speed=20&velocity=30&acceleration=60")
    assert (params.speed, params.acceleration) == (20, 60)


@pytest.mark.parametrize("path", ["/position", "/positions/run", "/poses/run"])
def test_every_motion_command_takes_the_sdk_parameters(
    spied: TestClient, spy: RecordingController, path: str
) -> None:
    target = spied.get("/pose" if "pose" in path else "/position").json()
    body = [target] if path.endswith("/run") else target
    query = {"velocity": 10, "acceleration": 20, "motionType": "LINEAR", "tcp_max_velocity": 1}
    response = spied.put(path, params=query, json=body)
    assert response.status_code == 200, response.text
    assert spy.motion_params[-1] == MotionParams(
        speed=10, motion_type=MotionType.LINEAR, tcp_max_velocity=1.0, acceleration=20
    )
