"""`pendant --no-ui --time-scale K`: a real process whose simulated time runs K times the wall clock, as a
client sees it through the API (motion status, the arm's pose, GET /sim/clock, gripper waits)."""

from __future__ import annotations

import time

import httpx
import pytest

from pendant.cli import parse_settings
from tests.support.launchers import running_pendant

pytestmark = pytest.mark.slow

# 20 times the wall clock: each motion and gripper wait here lasts seconds of wall clock, so a client starved
# of CPU for a while (the pass behind the timed tests, at nice 19) still sees it RUNNING (at 100 times, a
# 60 s motion was 0.6 s of wall clock).
SCALE = 20.0
FAR = {"angles": [270.0, -90.0, 90.0, -90.0, -90.0, 0.0]}  # J1 turns 270 degrees at speed 4: about 60 s
GRIPPER_MS = 60_000  # the longest gripper wait the API takes
POLL_S = 0.002


def wait_while_running(client: httpx.Client, limit_s: float = 60.0) -> str:
    deadline = time.monotonic() + limit_s
    while (status := client.get("/status/motion").json()) == "RUNNING":
        assert time.monotonic() < deadline, "the arm never stopped"
        time.sleep(POLL_S)
    return str(status)


def test_a_60_s_motion_runs_at_k_times_the_wall_clock() -> None:
    with running_pendant("--time-scale", f"{SCALE:g}") as url, httpx.Client(base_url=url) as client:
        outer0 = time.monotonic()  # before the first read is sent; `outer` ends after the second's answer
        before = client.get("/sim/clock").json()
        inner0 = time.monotonic()  # after the first read's answer; `inner` ends before the second is sent
        put0 = time.monotonic()
        client.put("/pose", params={"speed": 4}, json=FAR).raise_for_status()
        planning = time.monotonic() - put0  # the simulator plans inside it, its clock paused (no sim time)
        assert client.get("/status/motion").json() == "RUNNING"
        assert wait_while_running(client) == "IDLE"
        inner = time.monotonic() - inner0
        after = client.get("/sim/clock").json()
        outer = time.monotonic() - outer0
        simulated = after["time"] - before["time"]
        assert client.get("/pose").json()["angles"] == pytest.approx(FAR["angles"], abs=1e-6)
        assert after["scale"] == SCALE
        assert simulated > 55.0  # the motion's own length, in simulated seconds
        # Simulated seconds per wall second: the server read its clock inside `outer` and around `inner`
        # (less the PUT, whose planning takes no simulated time), so K times each brackets the simulated
        # span however long the client waited for the CPU.
        bounds = (SCALE * (inner - planning), SCALE * outer)
        assert 0.99 * bounds[0] <= simulated <= 1.01 * bounds[1], (simulated, bounds)
        assert after["timestamp"] - before["timestamp"] == pytest.approx(simulated, abs=1e-6)


def test_gripper_waits_and_motor_heating_follow_simulated_time() -> None:
    with running_pendant("--time-scale", f"{SCALE:g}") as url, httpx.Client(base_url=url) as client:
        t0 = client.get("/sim/clock").json()["time"]
        client.put("/gripper/close", params={"timeout": GRIPPER_MS}).raise_for_status()  # 60 s
        assert client.get("/status/motion").json() == "RUNNING"
        assert wait_while_running(client) == "IDLE"
        assert client.get("/sim/clock").json()["time"] - t0 >= GRIPPER_MS / 1000
        cold = [m["statorTemperature"] for m in client.get("/status/motors").json()]
        client.put("/pose", params={"speed": 4}, json=FAR).raise_for_status()
        wait_while_running(client)
        warm = [m["statorTemperature"] for m in client.get("/status/motors").json()]
        assert warm[0] > cold[0]  # a minute of J1 moving heats its stator, in 3 s of wall time


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
