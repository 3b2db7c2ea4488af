"""Jogging's safety rules, headless (a real viser server on loopback, the simulator on a fake clock): a
confirmation that arrives after a release never restarts the arm, no jog while a program runs, a jog in
ERROR names the cause and Recover sits under the banner, and the pad says when the TCP limit slows a joint."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionStatus, Pose
from pendant.jog import JogFrame, JogRequest
from pendant.program import RunState
from pendant.sim import FakeClock, Fault, SimController
from pendant.ui.app import PROGRAM_RUNNING, PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser, confirm_hold, fire
from tests.support.pages import button
from tests.support.sim_sampling import pose_deg

ANGLE_TOL_DEG = 1e-6
WAIT_S = 60.0  # a safety net: the page's threads starved of CPU (nice 19, a loaded machine) take seconds


@pytest.fixture
def operator() -> FakeBrowser:
    return FakeBrowser(OPERATOR)


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, what
        time.sleep(0.01)


def test_a_confirmation_sent_before_a_release_but_handled_after_it_does_not_restart_the_arm(
    pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    jogger = pendant_ui.jogger
    request = JogRequest(JogFrame.JOINT, 0, +1, speed_percent=10)
    assert jogger.hold(request, jogger.releases)
    clock.advance(0.5)
    sent_under = jogger.releases  # a confirmation leaves the page ...
    jogger.release("released")  # ... the release overtakes it on the server's threads
    stopped = pose_deg(sim)
    assert not jogger.hold(request, sent_under)
    clock.advance(1.0)
    assert sim.get_motion_status() is MotionStatus.IDLE
    np.testing.assert_allclose(pose_deg(sim), stopped, atol=ANGLE_TOL_DEG)
    assert jogger.hold(request, jogger.releases), "the next press jogs again"


def test_no_jog_or_move_from_the_page_while_a_program_runs(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    programs = pendant_ui.programs
    programs.record_from(sim)  # P1 here; then the arm goes elsewhere and the program brings it back
    sim.set_pose(Pose(angles=[40.0, -90.0, 90.0, -90.0, -90.0, 0.0]), MotionParams(speed=100.0))
    clock.advance(30.0)
    programs.start_run(loops=0)
    try:
        wait_for(lambda: programs.progress.state is RunState.RUNNING, "the program did not start")
        wait_for(lambda: sim.get_motion_status() is MotionStatus.RUNNING, "the program did not move")
        planned_end = sim.busy_until()
        confirm_hold(button(ui, "J1-"), operator)
        fire(ui.status.recover, operator)  # not a motion: never refused for a running program
        fire(ui.robot_buttons["Home"], operator)
        assert sim.busy_until() == planned_end, "a jog or Home was queued behind the program"
        assert any(PROGRAM_RUNNING in note for note in operator.notifications)
        assert sum("J1- refused" in note for note in operator.notifications) == 1, "once per press"
    finally:
        programs.stop()


def test_a_jog_in_error_names_the_error_and_recover_in_the_banner_clears_it(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    assert ui.banner is not None and ui.banner.view is None
    sim.inject_fault(Fault.ERROR)
    pendant_ui.refresh()
    assert "ERROR" in ui.status.content and ui.banner.buttons[0].visible
    assert ui.banner.buttons[0].label == "Recover"
    confirm_hold(button(ui, "J1+"), operator)
    (note,) = operator.notifications
    assert "The arm is in ERROR" in note and "Recover" in note, note
    fire(ui.banner.buttons[0], operator)
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "Recover did not clear the error")
    pendant_ui.refresh()
    assert ui.banner.view is None and not ui.banner.buttons[0].visible


def test_the_pad_says_when_the_tcp_limit_slows_a_joint_jog(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser
) -> None:
    fire(ui.jog.speed, operator, 10.0)
    pendant_ui.refresh()
    assert "250 mm/s" not in ui.jog.note.content  # 12°/s of J1 moves the TCP well under the limit
    fire(ui.jog.speed, operator, 100.0)
    pendant_ui.refresh()
    assert "The 250 mm/s TCP limit slows J1" in ui.jog.note.content
