"""Digital IO and the gripper."""

from __future__ import annotations

import pytest

from pendant.controller.types import MotionParams, MotionStatus, Pose, SignalLevel
from pendant.sim import FakeClock, SimController
from tests.support.sim_sampling import finish


def test_outputs_start_low_and_keep_what_they_are_set_to(sim: SimController) -> None:
    assert [sim.get_output(p) for p in (1, 2)] == [SignalLevel.LOW, SignalLevel.LOW]
    sim.set_output(2, SignalLevel.HIGH)
    assert sim.get_output(2) is SignalLevel.HIGH and sim.get_output(1) is SignalLevel.LOW
    sim.set_output(2, SignalLevel.LOW)
    assert sim.get_output(2) is SignalLevel.LOW


def test_inputs_follow_the_simulated_world(sim: SimController) -> None:
    assert [sim.get_input(p) for p in (1, 2, 3, 4)] == [SignalLevel.LOW] * 4
    sim.set_input(4, SignalLevel.HIGH)
    assert sim.get_input(4) is SignalLevel.HIGH
    assert sim.get_input(1) is SignalLevel.LOW


def test_the_gripper_closes_over_its_timeout(sim: SimController, clock: FakeClock) -> None:
    assert sim.gripper_opening() == 1.0
    sim.close_gripper(400)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    clock.advance(0.1)
    assert sim.gripper_opening() == pytest.approx(0.75)
    clock.advance(0.2)
    assert sim.gripper_opening() == pytest.approx(0.25)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    clock.advance(0.1)
    assert sim.gripper_opening() == 0.0
    assert sim.get_motion_status() is MotionStatus.IDLE
    clock.advance(100.0)
    assert sim.gripper_opening() == 0.0  # it stays closed


def test_a_zero_timeout_acts_at_once(sim: SimController) -> None:
    sim.close_gripper(0)
    assert sim.gripper_opening() == 0.0
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_a_gripper_command_waits_for_the_motion_before_it(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(Pose(angles=[30.0, -80.0, 80.0, -90.0, -90.0, 0.0]), MotionParams(speed=50))
    sim.close_gripper(500)
    clock.advance(0.2)
    assert sim.gripper_opening() == 1.0
    finish(sim, clock, step=0.05)
    assert sim.gripper_opening() == 0.0
    sim.open_gripper(500)
    finish(sim, clock, step=0.05)
    assert sim.gripper_opening() == 1.0
