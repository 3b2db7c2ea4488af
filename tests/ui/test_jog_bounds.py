"""The jog step and speed are checked by the server (issue #16, finding 4): a modified page sent step "500"
and J1 turned 346° in one step with no hold-to-run; "-10" and "1e9" were accepted too. Here the forged values
go in the way viser delivers them from a page (the control's value set, its callbacks fired), and the arm
must not move while the operator is told why."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.controller import MotionStatus
from pendant.jog import JogFrame, JogRefused, JogRequest
from pendant.jog.targets import MAX_STEP_M, MAX_STEP_RAD
from pendant.sim import FakeClock, SimController
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser, confirm_hold, fire
from tests.support.pages import button
from tests.support.sim_sampling import finish_motion, pose_deg

FORGED_STEPS = ["500", "-10", "1e9", "nan", "inf", "0", "0.5", "", "Continuous "]
FORGED_SPEEDS = [1e9, 0.0, -5.0, 100.5, math.nan, math.inf, "fifty", ""]


@pytest.fixture
def operator() -> FakeBrowser:
    return FakeBrowser(OPERATOR)


@pytest.mark.parametrize("frame", ["Joint", "Base"])
def test_a_forged_step_is_refused_and_the_arm_does_not_move(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock, frame: str
) -> None:
    fire(ui.jog.frame, operator, frame)
    before = pose_deg(sim)
    label = "J1+" if frame == "Joint" else "X+"
    for step in FORGED_STEPS:
        fire(ui.jog.step, operator, step)
        fire(button(ui, label), operator)
        finish_motion(sim, clock)
        np.testing.assert_array_equal(pose_deg(sim), before, err_msg=f"step {step!r}")
        assert sim.get_motion_status() is MotionStatus.IDLE
    refusal = f"{label} refused: Jog step must be one of Continuous, 0.1, 1, 10 (mm or °)"
    assert operator.notifications == [refusal] * len(FORGED_STEPS)


def test_a_forged_speed_is_refused_for_steps_and_holds(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    before = pose_deg(sim)
    for speed in FORGED_SPEEDS:
        fire(ui.jog.speed, operator, speed)
        fire(ui.jog.step, operator, "10")
        fire(button(ui, "J1+"), operator)
        fire(ui.jog.step, operator, "Continuous")
        confirm_hold(button(ui, "J1+"), operator)
        finish_motion(sim, clock)
        np.testing.assert_array_equal(pose_deg(sim), before, err_msg=f"speed {speed!r}")
        assert sim.get_motion_status() is MotionStatus.IDLE
    assert len(operator.notifications) == 2 * len(FORGED_SPEEDS)
    assert all(n.startswith("J1+ refused: Speed %: ") for n in operator.notifications)


def test_the_offered_largest_step_still_moves(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    fire(ui.jog.step, operator, "10")
    before = pose_deg(sim)
    fire(button(ui, "J1+"), operator)
    finish_motion(sim, clock)
    assert pose_deg(sim)[0] == pytest.approx(before[0] + 10.0)
    assert operator.notifications == []


@pytest.mark.parametrize(
    ("frame", "axis", "step"),
    [
        (JogFrame.JOINT, 0, math.radians(500)),
        (JogFrame.JOINT, 0, -MAX_STEP_RAD),
        (JogFrame.BASE, 0, MAX_STEP_M * 1.01),
        (JogFrame.BASE, 3, MAX_STEP_RAD * 1.01),
        (JogFrame.TOOL, 1, math.nan),
        (JogFrame.TOOL, 1, 0.0),
    ],
)
def test_a_jog_request_beyond_the_offered_steps_cannot_be_made(
    frame: JogFrame, axis: int, step: float
) -> None:
    with pytest.raises(JogRefused, match="Jog step must be above 0 and at most"):
        JogRequest(frame, axis, +1, 50.0, step)


@pytest.mark.parametrize(
    ("axis", "direction", "speed"), [(6, 1, 50.0), (-1, 1, 50.0), (0, 2, 50.0), (0, 1, 0.5)]
)
def test_a_jog_request_with_a_wrong_axis_direction_or_speed_cannot_be_made(
    axis: int, direction: int, speed: float
) -> None:
    with pytest.raises(JogRefused):
        JogRequest(JogFrame.JOINT, axis, direction, speed)
