"""Hold-to-run jogging on the simulator with a fake clock: moves while confirmed, freezes when not."""

from __future__ import annotations

import math
import threading
from typing import Any

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionStatus, Pose
from pendant.jog import DEADMAN_TIMEOUT_S, JOG_TCP_MAX_VELOCITY_M_S, JogFrame, Jogger, JogRequest
from pendant.sim import FakeClock, SimController
from tests.support.waiting import SAFETY_NET_S

CONFIRM_PERIOD_S = 0.05  # the page confirms at 20 Hz while the button is held
ANGLE_TOL_DEG = 1e-6
POS_TOL_M = 1e-6
THREAD_TIMEOUT_S = SAFETY_NET_S


def pose_deg(sim: SimController) -> np.ndarray:
    return np.asarray(sim.get_pose().angles)


def tcp_xyz(sim: SimController) -> np.ndarray:
    p = sim.get_position().point
    return np.array([p.x, p.y, p.z])


@pytest.fixture
def jogger(sim: SimController, clock: FakeClock) -> Jogger:
    return Jogger(sim, sim.arm, clock=clock.now)


def hold_for(jogger: Jogger, clock: FakeClock, request: JogRequest, seconds: float) -> None:
    """Confirm every CONFIRM_PERIOD_S for `seconds`, ending with a confirmation."""
    jogger.hold(request)
    for _ in range(round(seconds / CONFIRM_PERIOD_S)):
        clock.advance(CONFIRM_PERIOD_S)
        assert not jogger.check_deadman()
        jogger.hold(request)


def test_joint_jog_moves_only_the_held_joint_while_confirmed(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    before = pose_deg(sim)
    hold_for(jogger, clock, JogRequest(JogFrame.JOINT, 0, +1, speed_percent=10), 1.0)
    after = pose_deg(sim)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    assert after[0] > before[0] + 1.0
    np.testing.assert_allclose(after[1:], before[1:], atol=ANGLE_TOL_DEG)


def test_deadman_freezes_the_arm_when_confirmations_stop(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    hold_for(jogger, clock, JogRequest(JogFrame.JOINT, 0, +1, speed_percent=10), 0.5)
    clock.advance(DEADMAN_TIMEOUT_S * 0.9)
    assert not jogger.check_deadman()  # still inside the grace period
    clock.advance(DEADMAN_TIMEOUT_S * 0.2)
    assert jogger.check_deadman()
    stopped_at = pose_deg(sim)
    assert sim.get_motion_status() is MotionStatus.IDLE
    clock.advance(2.0)
    np.testing.assert_allclose(pose_deg(sim), stopped_at, atol=ANGLE_TOL_DEG)
    assert jogger.active is None


def test_release_stops_at_once(sim: SimController, clock: FakeClock, jogger: Jogger) -> None:
    hold_for(jogger, clock, JogRequest(JogFrame.JOINT, 2, -1, speed_percent=20), 0.4)
    jogger.release()
    stopped_at = pose_deg(sim)
    clock.advance(1.0)
    np.testing.assert_allclose(pose_deg(sim), stopped_at, atol=ANGLE_TOL_DEG)


def test_cartesian_base_z_jog_moves_the_tcp_straight_up(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    start = tcp_xyz(sim)
    hold_for(jogger, clock, JogRequest(JogFrame.BASE, 2, +1, speed_percent=50), 1.0)
    moved = tcp_xyz(sim) - start
    assert moved[2] > 0.02
    assert np.linalg.norm(moved[:2]) < 1e-4


def test_jog_speed_never_exceeds_250_mm_s_even_at_full_speed(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    request = JogRequest(JogFrame.JOINT, 1, +1, speed_percent=100)
    jogger.hold(request)
    previous = tcp_xyz(sim)
    dt = 0.01
    fastest = 0.0
    for i in range(100):
        clock.advance(dt)
        if i % 5 == 0:
            jogger.hold(request)
        now = tcp_xyz(sim)
        fastest = max(fastest, float(np.linalg.norm(now - previous)) / dt)
        previous = now
    assert fastest > 0.05
    assert fastest <= JOG_TCP_MAX_VELOCITY_M_S * 1.001


def test_step_jog_moves_exactly_one_increment_and_stops(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    before = pose_deg(sim)
    assert jogger.step(JogRequest(JogFrame.JOINT, 5, +1, speed_percent=50, step=math.radians(10)))
    clock.advance(5.0)
    assert sim.get_motion_status() is MotionStatus.IDLE
    np.testing.assert_allclose(pose_deg(sim) - before, [0, 0, 0, 0, 0, 10], atol=1e-6)


def test_tool_frame_step_moves_along_the_tool_axis(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    T_before = sim.arm.fk(np.radians(pose_deg(sim)))
    assert jogger.step(JogRequest(JogFrame.TOOL, 2, +1, speed_percent=50, step=0.01))
    clock.advance(5.0)
    T_after = sim.arm.fk(np.radians(pose_deg(sim)))
    np.testing.assert_allclose(T_after[:3, 3] - T_before[:3, 3], 0.01 * T_before[:3, 2], atol=1e-5)


def test_jog_into_the_floor_stops_short_and_reports_no_progress(
    sim: SimController, clock: FakeClock, jogger: Jogger
) -> None:
    request = JogRequest(JogFrame.BASE, 2, -1, speed_percent=100)
    for _ in range(400):
        if not jogger.hold(request):
            break
        clock.advance(CONFIRM_PERIOD_S)
    else:
        pytest.fail("jogging down never stopped")
    assert not sim.arm.in_collision(np.radians(pose_deg(sim)))
    assert sim.get_motion_status() is MotionStatus.IDLE


class SlowController:
    """The simulator behind a link that holds every motion command until the test lets it through."""

    def __init__(self, sim: SimController) -> None:
        self._sim = sim
        self.let_through = threading.Event()
        self.sending = threading.Event()
        self.freezes = 0

    def __getattr__(self, name: str) -> Any:  # the simulator's: a Controller to the type checker
        return getattr(self._sim, name)

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self.sending.set()
        assert self.let_through.wait(THREAD_TIMEOUT_S)
        self._sim.set_pose(pose, params)

    def freeze(self) -> None:
        self.freezes += 1
        self._sim.freeze()


def test_a_slow_controller_never_delays_the_deadman_and_a_late_motion_is_frozen(
    sim: SimController, clock: FakeClock
) -> None:
    slow = SlowController(sim)
    jogger = Jogger(slow, sim.arm, clock=clock.now)
    request = JogRequest(JogFrame.JOINT, 0, +1, speed_percent=10)
    pressing = threading.Thread(target=jogger.hold, args=(request,))
    pressing.start()
    assert slow.sending.wait(THREAD_TIMEOUT_S)  # the press is stuck on its way to the controller
    assert jogger.hold(request)  # a confirmation meanwhile does not queue behind it

    clock.advance(DEADMAN_TIMEOUT_S * 1.1)  # the operator let go
    assert jogger.check_deadman()  # fires at once, although the press still holds the link
    assert slow.freezes == 1

    slow.let_through.set()  # the press's motion reaches the controller only now ...
    pressing.join(THREAD_TIMEOUT_S)
    assert not pressing.is_alive()
    assert slow.freezes == 2  # ... and is frozen again at once
    assert sim.get_motion_status() is MotionStatus.IDLE
    stopped_at = pose_deg(sim)
    clock.advance(1.0)
    np.testing.assert_allclose(pose_deg(sim), stopped_at, atol=ANGLE_TOL_DEG)
