"""The Jog, IO, Simulator and Robot tabs headless: a real viser server on loopback, each control's callbacks
fired as a browser's click, hold or edit would fire them, the simulator on a fake clock."""

from __future__ import annotations

import math
from concurrent.futures import Future, wait

import numpy as np
import pytest
import viser
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller import MotionStatus, SignalLevel
from pendant.controller.errors import MSG_EMERGENCY, MSG_NOT_RESPONDING
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS
from pendant.jog import JOG_TCP_MAX_VELOCITY_M_S
from pendant.sim import FakeClock, Fault, SimController
from pendant.sim.controller import PACK_POSE_DEG
from pendant.ui.app import PendantUI
from pendant.ui.jog.panel import CONTINUOUS, DEFAULT_SPEED_PERCENT, HOLD_CONFIRM_HZ
from pendant.ui.kit.commands import HOME_POSE_DEG
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, confirm_hold, fire
from tests.support.pages import button
from tests.support.sim_sampling import finish_motion, pose_deg

ANGLE_TOL_DEG = 1e-6
POS_TOL_M = 1e-6
STEP_TOL = 1e-12  # a step size is a unit conversion, exact to rounding
SPEED_TOL_M_S = 1e-6
OPENING_TOL = 1e-9
FUTURE_TIMEOUT_S = 60.0  # a safety net: a thread starved of CPU (nice 19, a loaded machine) may take seconds
CONFIRM_PERIOD_S = 1.0 / HOLD_CONFIRM_HZ  # how often a held button calls back
SAMPLE_PERIOD_S = 0.01  # how finely the TCP speed is sampled on the fake clock
SETTLE_S = 0.1  # beyond the end of everything queued
JOINT_LABELS = [f"J{j}{s}" for j in range(1, 7) for s in "-+"]
CARTESIAN_LABELS = [f"{a}{s}" for a in ("X", "Y", "Z", "Roll", "Pitch", "Yaw") for s in "-+"]


class Commands:
    """Every command the page hands to the runner, so a test can wait for them instead of sleeping."""

    def __init__(self, page: PendantUI) -> None:
        self._futures: list[Future[object]] = []
        log = page.runner.on_submit

        def on_submit(
            label: str, client: viser.ClientHandle | None, refusal: str | None, future: Future[object] | None
        ) -> None:
            if log is not None:
                log(label, client, refusal, future)
            if future is not None:
                self._futures.append(future)

        page.runner.on_submit = on_submit

    def wait(self) -> None:
        """Until every command sent so far (and any they sent in turn) has finished."""
        done = 0
        while done < len(self._futures):
            pending = self._futures[done:]
            done = len(self._futures)
            _, not_done = wait(pending, timeout=FUTURE_TIMEOUT_S)
            assert not not_done, "a command did not finish"


@pytest.fixture
def commands(pendant_ui: PendantUI) -> Commands:
    return Commands(pendant_ui)


@pytest.fixture
def operator() -> FakeBrowser:
    return FakeBrowser(OPERATOR)


@pytest.fixture
def viewer() -> FakeBrowser:
    return FakeBrowser(VIEWER)


def tcp_xyz(sim: SimController) -> np.ndarray:
    p = sim.get_position().point
    return np.array([p.x, p.y, p.z])


def tcp_rpy(sim: SimController) -> np.ndarray:
    r = sim.get_position().rotation
    return np.array([r.roll, r.pitch, r.yaw])


def labels(ui: ClientSession) -> list[str]:
    return [ui.jog.buttons[(axis, direction)].label for axis in range(6) for direction in (-1, +1)]


# --- Jog ------------------------------------------------------------------------------------------------


def test_jog_buttons_are_labelled_by_the_frame(ui: ClientSession, operator: FakeBrowser) -> None:
    assert labels(ui) == JOINT_LABELS
    for frame in ("Base", "Tool"):
        fire(ui.jog.frame, operator, frame)
        assert labels(ui) == CARTESIAN_LABELS
    fire(ui.jog.frame, operator, "Joint")
    assert labels(ui) == JOINT_LABELS


def test_jog_starts_continuous_at_ten_percent(ui: ClientSession) -> None:
    assert ui.jog.step.value == CONTINUOUS
    assert ui.jog.speed.value == DEFAULT_SPEED_PERCENT == 10.0
    assert ui.jog.request(0, +1).step is None


@pytest.mark.parametrize("choice", ["0.1", "1", "10"])
def test_step_sizes_are_millimetres_for_xyz_and_degrees_otherwise(
    ui: ClientSession, operator: FakeBrowser, choice: str
) -> None:
    fire(ui.jog.step, operator, choice)
    amount = float(choice)
    fire(ui.jog.frame, operator, "Joint")
    assert ui.jog.request(0, +1).step == pytest.approx(math.radians(amount), abs=STEP_TOL)
    for frame in ("Base", "Tool"):
        fire(ui.jog.frame, operator, frame)
        for axis in range(3):  # X Y Z
            assert ui.jog.request(axis, +1).step == pytest.approx(amount / 1000.0, abs=STEP_TOL)
        for axis in range(3, 6):  # Roll Pitch Yaw
            assert ui.jog.request(axis, -1).step == pytest.approx(math.radians(amount), abs=STEP_TOL)


@pytest.mark.parametrize(("label", "choice", "joint", "sign"), [("J1+", "10", 0, +1), ("J3-", "1", 2, -1)])
def test_a_joint_step_click_turns_that_joint_by_exactly_the_step(
    ui: ClientSession,
    operator: FakeBrowser,
    sim: SimController,
    clock: FakeClock,
    label: str,
    choice: str,
    joint: int,
    sign: int,
) -> None:
    fire(ui.jog.step, operator, choice)
    before = pose_deg(sim)
    fire(button(ui, label), operator)
    finish_motion(sim, clock)
    expected = before.copy()
    expected[joint] += sign * float(choice)
    np.testing.assert_allclose(pose_deg(sim), expected, atol=ANGLE_TOL_DEG)
    assert sim.get_motion_status() is MotionStatus.IDLE


@pytest.mark.parametrize(("label", "choice", "axis", "sign"), [("X+", "10", 0, +1), ("Z-", "1", 2, -1)])
def test_a_base_step_click_moves_the_tcp_by_exactly_the_step(
    ui: ClientSession,
    operator: FakeBrowser,
    sim: SimController,
    clock: FakeClock,
    label: str,
    choice: str,
    axis: int,
    sign: int,
) -> None:
    fire(ui.jog.frame, operator, "Base")
    fire(ui.jog.step, operator, choice)
    start, start_rpy = tcp_xyz(sim), tcp_rpy(sim)
    fire(button(ui, label), operator)
    finish_motion(sim, clock)
    expected = start.copy()
    expected[axis] += sign * float(choice) / 1000.0
    np.testing.assert_allclose(tcp_xyz(sim), expected, atol=POS_TOL_M)
    np.testing.assert_allclose(tcp_rpy(sim), start_rpy, atol=POS_TOL_M)


def test_a_rotation_step_click_turns_the_tool_by_exactly_the_step(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    fire(ui.jog.frame, operator, "Base")
    fire(ui.jog.step, operator, "10")
    start, start_rpy = tcp_xyz(sim), tcp_rpy(sim)
    fire(button(ui, "Yaw+"), operator)
    finish_motion(sim, clock)
    assert math.degrees(tcp_rpy(sim)[2] - start_rpy[2]) == pytest.approx(10.0, abs=ANGLE_TOL_DEG)
    np.testing.assert_allclose(tcp_xyz(sim), start, atol=POS_TOL_M)  # about the TCP: it stays put


def test_holding_a_jog_button_moves_the_arm_and_releasing_it_stops_it(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    before = pose_deg(sim)
    j1_plus = button(ui, "J1+")
    confirm_hold(j1_plus, operator)
    for _ in range(20):  # one second held
        clock.advance(CONFIRM_PERIOD_S)
        confirm_hold(j1_plus, operator)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    held = pose_deg(sim)
    assert held[0] > before[0] + 1.0
    np.testing.assert_allclose(held[1:], before[1:], atol=ANGLE_TOL_DEG)

    fire(j1_plus, operator)  # the browser sends the click when the button is let go
    stopped = pose_deg(sim)
    assert sim.get_motion_status() is MotionStatus.IDLE
    clock.advance(2.0)
    np.testing.assert_allclose(pose_deg(sim), stopped, atol=ANGLE_TOL_DEG)


def test_a_viewer_holding_a_jog_button_does_not_move_the_arm(
    ui: ClientSession, viewer: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    before = pose_deg(sim)
    confirm_hold(button(ui, "J1+"), viewer)
    clock.advance(1.0)
    np.testing.assert_allclose(pose_deg(sim), before, atol=ANGLE_TOL_DEG)
    assert viewer.notifications and "viewer" in viewer.notifications[0]


@pytest.mark.parametrize(
    ("frame", "label"), [("Base", "X+"), ("Base", "X-"), ("Base", "Pitch+"), ("Joint", "J1+")]
)
def test_jogging_at_full_speed_never_exceeds_250_mm_s_at_the_tcp(
    ui: ClientSession,
    operator: FakeBrowser,
    sim: SimController,
    clock: FakeClock,
    frame: str,
    label: str,
) -> None:
    fire(ui.jog.frame, operator, frame)
    fire(ui.jog.speed, operator, 100.0)
    held = button(ui, label)
    start_q, previous = pose_deg(sim), tcp_xyz(sim)
    speeds = []
    confirm_hold(held, operator)
    for _ in range(40):  # two seconds held, the TCP sampled every SAMPLE_PERIOD_S in between
        for _ in range(round(CONFIRM_PERIOD_S / SAMPLE_PERIOD_S)):
            clock.advance(SAMPLE_PERIOD_S)
            now = tcp_xyz(sim)
            speeds.append(np.linalg.norm(now - previous) / SAMPLE_PERIOD_S)
            previous = now
        confirm_hold(held, operator)
    fire(held, operator)
    assert np.max(np.abs(pose_deg(sim) - start_q)) > 5.0, "the jog went somewhere"
    assert max(speeds) <= JOG_TCP_MAX_VELOCITY_M_S + SPEED_TOL_M_S


# --- IO -------------------------------------------------------------------------------------------------


def test_the_do1_toggle_sets_the_controller_output(
    ui: ClientSession, pendant_ui: PendantUI, commands: Commands, operator: FakeBrowser, sim: SimController
) -> None:
    fire(ui.io.outputs[1], operator, True)
    commands.wait()
    assert sim.get_output(1) is SignalLevel.HIGH
    assert sim.get_output(2) is SignalLevel.LOW
    pendant_ui.refresh()
    assert ui.io.outputs[1].value is True

    fire(ui.io.outputs[1], operator, False)
    commands.wait()
    assert sim.get_output(1) is SignalLevel.LOW


def test_a_viewers_output_toggle_is_refused_and_springs_back(
    ui: ClientSession, pendant_ui: PendantUI, commands: Commands, viewer: FakeBrowser, sim: SimController
) -> None:
    fire(ui.io.outputs[1], viewer, True)
    commands.wait()
    assert sim.get_output(1) is SignalLevel.LOW
    assert viewer.notifications and "DO1" in viewer.notifications[0]
    assert ui.io.outputs[1].value is False
    pendant_ui.refresh()
    assert ui.io.outputs[1].value is False


@pytest.mark.parametrize(
    ("fault", "message"), [(Fault.EMERGENCY, MSG_EMERGENCY), (Fault.NO_RESPONSE, MSG_NOT_RESPONDING)]
)
def test_an_output_write_the_controller_refuses_springs_back(
    ui: ClientSession,
    pendant_ui: PendantUI,
    commands: Commands,
    operator: FakeBrowser,
    sim: SimController,
    fault: Fault,
    message: str,
) -> None:
    sim.inject_fault(fault)
    pendant_ui.refresh()  # the controller cannot be read now: nothing to read the outputs back from
    fire(ui.io.outputs[2], operator, True)
    commands.wait()
    assert ui.io.outputs[2].value is False
    assert operator.notifications == [f"DO2 HIGH refused: {message}"]


def test_input_indicators_follow_the_simulators_inputs(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    sim.set_input(2, SignalLevel.HIGH)
    sim.set_input(4, SignalLevel.HIGH)
    pendant_ui.refresh()
    assert {port: box.value for port, box in ui.io.inputs.items()} == {1: False, 2: True, 3: False, 4: True}
    assert all(box.disabled for box in ui.io.inputs.values()), "an indicator, not a switch"
    sim.set_input(2, SignalLevel.LOW)
    pendant_ui.refresh()
    assert ui.io.inputs[2].value is False and ui.io.inputs[4].value is True


def test_gripper_buttons_close_and_open_the_gripper_over_time(
    ui: ClientSession, pendant_ui: PendantUI, commands: Commands, operator: FakeBrowser, clock: FakeClock
) -> None:
    duration_s = DEFAULT_GRIPPER_TIMEOUT_MS / 1000.0
    assert pendant_ui.refresh().gripper_opening == pytest.approx(1.0, abs=OPENING_TOL)
    for gripper_button, opening in ((ui.io.gripper_close, 0.0), (ui.io.gripper_open, 1.0)):
        fire(gripper_button, operator)
        commands.wait()
        clock.advance(duration_s / 2)
        halfway = pendant_ui.refresh().gripper_opening
        assert halfway is not None and 0.0 < halfway < 1.0  # on its way, over the timeout
        clock.advance(duration_s)
        assert pendant_ui.refresh().gripper_opening == pytest.approx(opening, abs=OPENING_TOL)


# --- Simulator --------------------------------------------------------------------------------------------


def test_simulator_switches_set_the_inputs(
    ui: ClientSession, pendant_ui: PendantUI, commands: Commands, operator: FakeBrowser, sim: SimController
) -> None:
    assert ui.sim_panel is not None
    fire(ui.sim_panel.inputs[3], operator, True)
    commands.wait()
    assert sim.get_input(3) is SignalLevel.HIGH
    assert sim.get_input(1) is SignalLevel.LOW
    pendant_ui.refresh()
    assert ui.io.inputs[3].value is True  # and the IO tab's indicator shows it
    fire(ui.sim_panel.inputs[3], operator, False)
    commands.wait()
    assert sim.get_input(3) is SignalLevel.LOW


@pytest.mark.parametrize(
    ("fault", "status", "message"),
    [
        (Fault.ERROR, MotionStatus.ERROR, None),
        (Fault.EMERGENCY, MotionStatus.EMERGENCY, MSG_EMERGENCY),
        (Fault.NO_RESPONSE, None, MSG_NOT_RESPONDING),
    ],
)
def test_fault_buttons_inject_the_fault_and_reset_clears_it(
    ui: ClientSession,
    pendant_ui: PendantUI,
    commands: Commands,
    operator: FakeBrowser,
    sim: SimController,
    clock: FakeClock,
    fault: Fault,
    status: MotionStatus | None,
    message: str | None,
) -> None:
    assert ui.sim_panel is not None
    fire(ui.sim_panel.inputs[1], operator, True)
    fire(ui.sim_panel.faults[fault], operator)
    commands.wait()
    snapshot = pendant_ui.refresh()
    assert snapshot.motion_status is status and snapshot.error == message

    fire(ui.sim_panel.reset, operator)  # asks first
    assert "Reset the simulator?" in ui.sim_panel.confirmation.question.content
    fire(ui.sim_panel.confirmation.buttons, operator, "Yes")
    commands.wait()
    snapshot = pendant_ui.refresh()
    assert snapshot.motion_status is MotionStatus.IDLE and snapshot.error is None
    assert sim.get_input(1) is SignalLevel.LOW and ui.sim_panel.inputs[1].value is False
    assert ui.io.inputs[1].value is False


# --- Robot ------------------------------------------------------------------------------------------------


def test_home_goes_to_the_home_pose(
    ui: ClientSession, commands: Commands, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    assert HOME_POSE_DEG == (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
    fire(ui.robot_buttons["Home"], operator)
    commands.wait()
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish_motion(sim, clock)
    np.testing.assert_allclose(pose_deg(sim), HOME_POSE_DEG, atol=ANGLE_TOL_DEG)


def test_relax_makes_the_arm_free_to_move_by_hand(
    ui: ClientSession, commands: Commands, operator: FakeBrowser, sim: SimController
) -> None:
    fire(ui.robot_buttons["Relax"], operator)
    commands.wait()
    assert sim.get_motion_status() is MotionStatus.ZERO_GRAVITY


def test_recover_after_an_injected_error_returns_to_idle(
    ui: ClientSession, pendant_ui: PendantUI, commands: Commands, operator: FakeBrowser, sim: SimController
) -> None:
    assert ui.sim_panel is not None
    fire(ui.sim_panel.faults[Fault.ERROR], operator)
    commands.wait()
    assert pendant_ui.refresh().motion_status is MotionStatus.ERROR
    fire(ui.status.recover, operator)
    commands.wait()
    assert pendant_ui.refresh().motion_status is MotionStatus.IDLE


def test_pack_moves_towards_the_transport_pose(
    ui: ClientSession, commands: Commands, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    def distance() -> float:
        return float(np.max(np.abs(pose_deg(sim) - PACK_POSE_DEG)))

    start = distance()
    fire(ui.robot_buttons["Pack"], operator)
    commands.wait()
    clock.advance(0.5)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    assert distance() < start
    finish_motion(sim, clock)
    np.testing.assert_allclose(pose_deg(sim), PACK_POSE_DEG, atol=ANGLE_TOL_DEG)


# --- Settings ---------------------------------------------------------------------------------------------


@pytest.fixture
def api(sim: SimController) -> TestClient:
    return TestClient(create_app(sim))


@pytest.mark.parametrize(
    ("xyz_mm", "rpy_deg"),
    [
        ((0.0, 0.0, 5000.0), (0.0, 0.0, 0.0)),  # five metres: a typing error
        ((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0)),
        ((0.0, 0.0, 0.0), (0.0, float("inf"), 0.0)),
    ],
)
def test_an_invalid_base_form_is_refused_before_sending(
    ui: ClientSession,
    commands: Commands,
    operator: FakeBrowser,
    api: TestClient,
    xyz_mm: tuple[float, float, float],
    rpy_deg: tuple[float, float, float],
) -> None:
    before = api.get("/base").json()
    fire(ui.settings.base_xyz, operator, xyz_mm)
    fire(ui.settings.base_rpy, operator, rpy_deg)
    fire(ui.settings.set_base, operator)
    commands.wait()
    assert api.get("/base").json() == before
    assert len(operator.notifications) == 1 and operator.notifications[0].startswith("Base not set")


def test_a_valid_base_form_changes_the_zero_point(
    ui: ClientSession, commands: Commands, operator: FakeBrowser, api: TestClient
) -> None:
    fire(ui.settings.base_xyz, operator, (100.0, -50.0, 20.0))
    fire(ui.settings.base_rpy, operator, (0.0, 0.0, 90.0))
    fire(ui.settings.set_base, operator)
    commands.wait()
    base = api.get("/base").json()
    point, rotation = base["point"], base["rotation"]
    np.testing.assert_allclose([point["x"], point["y"], point["z"]], [0.1, -0.05, 0.02], atol=POS_TOL_M)
    np.testing.assert_allclose(
        [rotation["roll"], rotation["pitch"], rotation["yaw"]], [0.0, 0.0, math.pi / 2], atol=POS_TOL_M
    )
    assert operator.notifications == []
