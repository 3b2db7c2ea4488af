"""A script written with Rozum's official SDK (pulse-api 1.5.0) runs unchanged against the simulator."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path
from typing import Any

import httpx
import pytest

from tests.support.api_client import ANGLE_TOL_DEG, POS_TOL_M
from tests.support.launchers import REPO_ROOT, running_pendant

pytestmark = [pytest.mark.sdk, pytest.mark.slow]

SDK_PYTHON = REPO_ROOT / ".venv-sdk" / "bin" / "python"
SCRIPT = Path(__file__).with_name("sdk_script.py")
SCRIPT_TIMEOUT_S = 120.0


@pytest.fixture(scope="module")
def report() -> dict[str, Any]:
    """What the SDK script read while driving the simulator over HTTP."""
    assert SDK_PYTHON.exists(), "create the SDK venv first: make .venv-sdk/.installed"
    with running_pendant() as base_url:
        httpx.put(f"{base_url}/sim/signal/input/2/high", timeout=30.0).raise_for_status()
        run = subprocess.run(
            [str(SDK_PYTHON), str(SCRIPT), base_url],
            capture_output=True,
            text=True,
            timeout=SCRIPT_TIMEOUT_S,
            check=False,
        )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def assert_angles(actual: list[float], expected: list[float]) -> None:
    assert actual == pytest.approx(expected, abs=ANGLE_TOL_DEG)


def assert_position(actual: dict[str, list[float]], expected: dict[str, list[float]]) -> None:
    assert actual["point"] == pytest.approx(expected["point"], abs=POS_TOL_M)


def test_reads_come_back_as_sdk_objects(report: dict[str, Any]) -> None:
    assert isinstance(report["identifier"], str) and report["identifier"]
    assert len(report["start_pose"]) == 6
    assert report["status_motors_count"] == 6
    assert report["motor_angle_0"] == pytest.approx(report["start_pose"][0], abs=ANGLE_TOL_DEG)


def test_set_pose_with_speed_moves_the_arm_there(report: dict[str, Any]) -> None:
    assert report["status_while_moving"] == "RUNNING"
    assert_angles(report["pose_after_set_pose"], report["pose_target"])


def test_run_poses_ends_at_the_last_waypoint(report: dict[str, Any]) -> None:
    assert_angles(report["pose_after_run_poses"], report["run_poses_target"])


def test_set_position_with_velocity_acceleration_and_linear_type(report: dict[str, Any]) -> None:
    assert_position(report["position_after_set_position"], report["set_position_target"])


def test_run_positions_ends_at_the_last_waypoint(report: dict[str, Any]) -> None:
    assert_position(report["position_after_run_positions"], report["run_positions_target"])


def test_signals_read_as_the_sdks_enum_values(report: dict[str, Any]) -> None:
    assert (report["output_1_after_high"], report["output_2_untouched"]) == ("HIGH", "LOW")
    assert report["output_1_after_low"] == "LOW"
    assert report["input_2"] == "HIGH"


def test_state_commands_and_recover(report: dict[str, Any]) -> None:
    assert report["status_relaxed"] == "ZERO_GRAVITY"
    assert report["status_frozen"] == "IDLE"
    assert report["recover"] == "SUCCESS"


def test_change_base_answers_and_keeps_the_new_base(report: dict[str, Any]) -> None:
    expected = {"point": [0.1, -0.05, 0.02], "rotation": [0.0, 0.0, 0.3]}
    assert_position(report["change_base_answer"], expected)
    assert_position(report["base"], expected)
    assert report["base"]["rotation"] == pytest.approx(expected["rotation"], abs=POS_TOL_M)
