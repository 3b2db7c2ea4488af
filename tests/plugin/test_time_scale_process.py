"""`pendant --no-ui --time-scale K`: a real process whose simulated time runs K times the wall clock, as a
client sees it through the API (motion status, the arm's pose, GET /sim/clock, gripper waits)."""

from __future__ import annotations

import time

import httpx
import pytest

from pendant.cli import parse_settings
from tests.support.launchers import running_pendant

pytestmark = pytest.mark.slow

SCALE = 100.0
FAR = {"angles": [270.0, -90.0, 90.0, -90.0, -90.0, 0.0]}  # J1 turns 270 degrees at speed 4: about 60 s
POLL_S = 0.002


def wait_while_running(client: httpx.Client, limit_s: float = 30.0) -> str:
    deadline = time.monotonic() + limit_s
    while (status := client.get("/status/motion").json()) == "RUNNING":
        assert time.monotonic() < deadline, "the arm never stopped"
        time.sleep(POLL_S)
    return str(status)


def test_a_60_s_motion_runs_at_k_times_the_wall_clock() -> None:
    with running_pendant("--time-scale", f"{SCALE:g}") as url, httpx.Client(base_url=url) as client:
        before, wall0 = client.get("/sim/clock").json(), time.monotonic()
        client.put("/pose", params={"speed": 4}, json=FAR).raise_for_status()
        assert client.get("/status/motion").json() == "RUNNING"
        assert wait_while_running(client) == "IDLE"
        after, wall = client.get("/sim/clock").json(), time.monotonic() - wall0
        simulated = after["time"] - before["time"]
        assert client.get("/pose").json()["angles"] == pytest.approx(FAR["angles"], abs=1e-6)
        assert after["scale"] == SCALE
        assert simulated > 55.0  # the motion's own length, in simulated seconds
        # Side by side: simulated seconds per wall second, as the client measured both.
        assert 0.5 * SCALE < simulated / wall <= 1.01 * SCALE
        assert after["timestamp"] - before["timestamp"] == pytest.approx(simulated, abs=1e-6)


def test_gripper_waits_and_motor_heating_follow_simulated_time() -> None:
    with running_pendant("--time-scale", f"{SCALE:g}") as url, httpx.Client(base_url=url) as client:
        t0 = client.get("/sim/clock").json()["time"]
        client.put("/gripper/close", params={"timeout": 30000}).raise_for_status()  # 30 s
        assert client.get("/status/motion").json() == "RUNNING"
        assert wait_while_running(client) == "IDLE"
        assert client.get("/sim/clock").json()["time"] - t0 >= 30.0
        cold = [m["statorTemperature"] for m in client.get("/status/motors").json()]
        client.put("/pose", params={"speed": 4}, json=FAR).raise_for_status()
        wait_while_running(client)
        warm = [m["statorTemperature"] for m in client.get("/status/motors").json()]
        assert warm[0] > cold[0]  # a minute of J1 moving heats its stator, in a second of wall time


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--robot", "http://127.0.0.1:9", "--time-scale", "10"], "use it without --robot"),
        (["--no-ui", "--robot", "http://127.0.0.1:9", "--time-scale", "10"], "without --robot"),
        (["--no-ui", "--time-scale", "0.05"], "time scale must be between 0.1 and 1000 (got 0.05)"),
        (["--no-ui", "--time-scale", "5000"], "time scale must be between 0.1 and 1000 (got 5000)"),
        (["--no-ui", "--time-scale", "fast"], "invalid float value: 'fast'"),
    ],
)
def test_bad_time_scales_are_refused(
    argv: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exit_info:
        parse_settings(argv)
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err


def test_time_scale_lands_in_settings() -> None:
    assert parse_settings(["--no-ui", "--time-scale", "250"]).time_scale == 250.0
    assert parse_settings(["--time-scale", "10"]).time_scale == 10.0  # with the page too (tests/browser)
    assert parse_settings([]).time_scale == 1.0
