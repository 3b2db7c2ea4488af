# A user's test file for the pulse_sim fixture: written into a temp project and run there by pytest in a
# subprocess (tests/plugin/test_user_project.py). It is not collected here (no test_ prefix in its name).
import math
import os
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from pendant.testing import FAULT_KINDS, PulseSim, PulseSimError

HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
FAR = [270.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # J1 turns 270 degrees: about 60 s at speed 4
SLOW = {"speed": 4}
URLS = Path(__file__).with_name("urls")


@pytest.fixture
def api(pulse_sim: PulseSim) -> Iterator[httpx.Client]:
    URLS.mkdir(exist_ok=True)
    worker = os.environ.get("PYTEST_XDIST_WORKER", "main")
    (URLS / f"{worker}-{time.monotonic_ns()}.txt").write_text(pulse_sim.url)
    # A safety net (tests.support.waiting.SAFETY_NET_S, which this project cannot import): `make test` runs
    # it in the idle class, where a request may get no CPU for seconds.
    with httpx.Client(base_url=pulse_sim.url, timeout=30.0) as client:
        yield client


def motion_status(api: httpx.Client) -> str:
    return api.get("/status/motion").json()


def wait_while_running(api: httpx.Client, limit_s: float = 60.0) -> str:
    deadline = time.monotonic() + limit_s
    while motion_status(api) == "RUNNING":
        assert time.monotonic() < deadline, "the arm never stopped"
        time.sleep(0.002)
    return motion_status(api)


def angles(api: httpx.Client) -> list[float]:
    return api.get("/pose").json()["angles"]


def test_a_changes_everything(pulse_sim: PulseSim, api: httpx.Client) -> None:
    api.put("/signal/output/1/high").raise_for_status()
    pulse_sim.set_input(2, "high")
    assert api.get("/signal/input/2").json() == "HIGH"
    api.put("/relax").raise_for_status()
    pulse_sim.move_by_hand([10.0, -80.0, 80.0, -90.0, -90.0, 0.0])
    assert angles(api) == pytest.approx([10.0, -80.0, 80.0, -90.0, -90.0, 0.0])
    pulse_sim.at(100.0, "error")  # never reached in this test: must not leak into the next
    pulse_sim.fault("emergency")
    assert api.get("/pose").status_code == 503


def test_b_starts_from_power_on(pulse_sim: PulseSim, api: httpx.Client) -> None:
    assert motion_status(api) == "IDLE"
    assert api.get("/signal/output/1").json() == "LOW"
    assert api.get("/signal/input/2").json() == "LOW"
    assert angles(api) == pytest.approx(HOME)
    assert pulse_sim.time < 100.0


def test_every_fault_that_refuses_motion(pulse_sim: PulseSim, api: httpx.Client) -> None:
    have = pulse_sim.fault_kinds()
    assert {"error", "emergency", "no_response", "motion_failed", "overheat"} <= set(have)
    for kind in FAULT_KINDS:
        if kind not in have:
            with pytest.raises(PulseSimError, match="not in this simulator yet"):
                pulse_sim.fault(kind)
    for kind in (k for k in have if k not in ("motion_failed", "overheat")):
        pulse_sim.controller.reset()
        pulse_sim.fault(kind)
        refused = api.put("/pose", params=SLOW, json={"angles": FAR})
        assert refused.status_code in (412, 500, 503), (kind, refused.text)
        pulse_sim.controller.reset()
        assert angles(api) == pytest.approx(HOME), kind


def test_error_message_and_recover(pulse_sim: PulseSim, api: httpx.Client) -> None:
    pulse_sim.fault("error")
    refused = api.put("/pose", params=SLOW, json={"angles": FAR})
    assert (refused.status_code, refused.json()) == (500, "Robot does not respond")
    assert motion_status(api) == "ERROR"
    assert api.put("/recover").json() == "SUCCESS"


def test_overheat_heats_the_stators(pulse_sim: PulseSim, api: httpx.Client) -> None:
    cold = max(m["statorTemperature"] for m in api.get("/status/motors").json())
    pulse_sim.fault("overheat")
    hot = max(m["statorTemperature"] for m in api.get("/status/motors").json())
    assert cold < 40.0 < 100.0 < hot


def test_unknown_fault_is_refused(pulse_sim: PulseSim) -> None:
    with pytest.raises(PulseSimError, match="unknown fault 'meltdown'"):
        pulse_sim.fault("meltdown")


def test_motion_failed_stops_the_moving_arm(pulse_sim: PulseSim, api: httpx.Client) -> None:
    api.put("/pose", params=SLOW, json={"angles": FAR}).raise_for_status()
    time.sleep(0.05)
    pulse_sim.fault("motion_failed")
    assert motion_status(api) == "MOTION_FAILED"
    stopped = angles(api)
    assert HOME[0] < stopped[0] < FAR[0]
    time.sleep(0.05)
    assert angles(api) == stopped


@pytest.mark.pulse_sim(time_scale=100)
def test_at_a_simulated_time_exactly(pulse_sim: PulseSim, api: httpx.Client) -> None:
    # Scripted before the move: at 100 times the wall clock, 30 s go by in 0.3 s of a busy machine.
    event = pulse_sim.at(30.0, "error")
    api.put("/pose", params=SLOW, json={"angles": FAR}).raise_for_status()
    (motion,) = pulse_sim.controller.queued_motions()
    assert wait_while_running(api) == "ERROR"
    assert event.fired_at == pytest.approx(30.0, abs=1e-9)
    expected = [math.degrees(a) for a in motion.q_at(pulse_sim.origin + 30.0)]
    assert angles(api) == pytest.approx(expected, abs=1e-9)


@pytest.mark.pulse_sim(time_scale=100)
def test_when_a_waypoint_is_reached(pulse_sim: PulseSim, api: httpx.Client) -> None:
    event = pulse_sim.on_waypoint(2, "emergency")
    run = [{"angles": [j1, -90.0, 90.0, -90.0, -90.0, 0.0]} for j1 in (30.0, 60.0, 90.0)]
    api.put("/poses/run", params={"speed": 20}, json=run).raise_for_status()
    deadline = time.monotonic() + 30.0
    while api.get("/pose").status_code == 200:
        assert time.monotonic() < deadline
        time.sleep(0.002)
    assert event.fired_at is not None
    pulse_sim.controller.reset()  # read the arm where the emergency left it: through the simulator
    assert event.fired_at > 0.5


@pytest.mark.pulse_sim(time_scale=100)
def test_waypoint_error_leaves_the_arm_at_the_waypoint(pulse_sim: PulseSim, api: httpx.Client) -> None:
    pulse_sim.on_waypoint(2, "error")
    run = [{"angles": [j1, -90.0, 90.0, -90.0, -90.0, 0.0]} for j1 in (30.0, 60.0, 90.0)]
    api.put("/poses/run", params={"speed": 20}, json=run).raise_for_status()
    assert wait_while_running(api) == "ERROR"
    assert angles(api) == pytest.approx(run[1]["angles"], abs=0.01)


def test_waypoint_of_the_run_already_moving(pulse_sim: PulseSim, api: httpx.Client) -> None:
    run = [{"angles": [j1, -90.0, 90.0, -90.0, -90.0, 0.0]} for j1 in (30.0, 60.0, 90.0)]
    api.put("/poses/run", params={"speed": 5}, json=run).raise_for_status()
    assert motion_status(api) == "RUNNING"
    pulse_sim.on_waypoint(2, "error")
    assert wait_while_running(api) == "ERROR"
    assert angles(api) == pytest.approx(run[1]["angles"], abs=0.01)


@pytest.mark.pulse_sim(time_scale=100)
def test_waypoint_of_a_linear_positions_run(pulse_sim: PulseSim, api: httpx.Client) -> None:
    start = api.get("/position").json()
    points = [dict(start, point=dict(start["point"], x=start["point"]["x"] + dx)) for dx in (0.05, 0.1, 0.15)]
    pulse_sim.on_waypoint(1, "error")
    params: dict[str, str | int] = {"speed": 20, "type": "LINEAR"}
    api.put("/positions/run", params=params, json=points).raise_for_status()
    assert wait_while_running(api) == "ERROR"
    stopped = api.get("/position").json()["point"]
    assert stopped["x"] == pytest.approx(points[0]["point"]["x"], abs=0.0015)


@pytest.mark.pulse_sim(time_scale=1000)
def test_a_moment_already_past_is_refused(pulse_sim: PulseSim) -> None:
    while pulse_sim.time < 1.0:
        time.sleep(0.001)
    with pytest.raises(ValueError, match="the test's simulated time is already"):
        pulse_sim.at(0.5, "error")


def test_on_the_nth_command(pulse_sim: PulseSim, api: httpx.Client) -> None:
    event = pulse_sim.on_command(2, "no_response")
    assert api.put("/signal/output/1/high").status_code == 200
    second = api.put("/signal/output/2/high")
    assert (second.status_code, second.json()) == (500, "Robot does not respond")
    assert event.fired_at is not None


@pytest.mark.pulse_sim(time_scale=50)
def test_a_function_as_the_action(pulse_sim: PulseSim, api: httpx.Client) -> None:
    event = pulse_sim.at(2.0, lambda: pulse_sim.set_input(1, True))
    deadline = time.monotonic() + 60.0
    while api.get("/signal/input/1").json() != "HIGH":
        assert time.monotonic() < deadline
        time.sleep(0.002)
    assert event.fired_at == pytest.approx(2.0, abs=1e-9)
    assert pulse_sim.time >= 2.0


@pytest.mark.pulse_sim(time_scale=100)
def test_a_60_s_motion_takes_a_fraction_of_it(pulse_sim: PulseSim, api: httpx.Client) -> None:
    api.put("/pose", params=SLOW, json={"angles": FAR}).raise_for_status()
    (motion,) = pulse_sim.controller.queued_motions()
    outer0 = time.monotonic()  # before the first read and after the second: the server's span is inside
    before = api.get("/sim/clock").json()
    inner0 = time.monotonic()  # after the first read and before the second: inside the server's span
    assert wait_while_running(api) == "IDLE"
    inner = time.monotonic() - inner0
    after = api.get("/sim/clock").json()
    outer = time.monotonic() - outer0
    assert motion.duration > 55.0
    assert angles(api) == pytest.approx(FAR, abs=1e-6)
    simulated = after["time"] - before["time"]
    assert simulated >= motion.t_end - before["time"]
    assert 99.0 * inner <= simulated <= 101.0 * outer, (simulated, inner, outer)  # however slow the client
    assert after["timestamp"] - before["timestamp"] == pytest.approx(simulated, abs=1e-6)
    assert after["scale"] == 100.0


@pytest.mark.pulse_sim(time_scale=20)  # the 60 s wait is 3 s of wall clock: still RUNNING when we look
def test_gripper_waits_scale_too(pulse_sim: PulseSim, api: httpx.Client) -> None:
    t0 = api.get("/sim/clock").json()["time"]
    api.put("/gripper/close", params={"timeout": 60000}).raise_for_status()  # 60 s, the longest
    assert motion_status(api) == "RUNNING"
    assert wait_while_running(api) == "IDLE"
    assert api.get("/sim/clock").json()["time"] - t0 >= 60.0


@pytest.mark.pulse_sim(model="pulse90")
def test_model_option(pulse_sim: PulseSim, api: httpx.Client) -> None:
    assert pulse_sim.model == "pulse90"
    assert pulse_sim.controller.arm.name == "pulse90"


def test_user_code_meets_the_scripted_error(pulse_sim: PulseSim, api: httpx.Client) -> None:
    # Robot code that does not expect a failure: this test must fail, showing the controller's message.
    pulse_sim.on_command(1, "error")
    api.put("/pose", params=SLOW, json={"angles": FAR}).raise_for_status()


def test_waypoint_the_run_does_not_have(pulse_sim: PulseSim, api: httpx.Client) -> None:
    # Scripted against a waypoint the run lacks: reported as an error at teardown.
    pulse_sim.on_waypoint(5, "error")
    api.put("/pose", params=SLOW, json={"angles": FAR}).raise_for_status()
