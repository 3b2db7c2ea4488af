"""Servo telemetry: plausible numbers that follow the arm's motion and load."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.types import MotionParams, Pose
from pendant.sim import FakeClock, SimController
from tests.support.sim_sampling import finish

UPRIGHT = Pose(angles=[0.0, -90.0, 0.0, -90.0, -90.0, 0.0])  # the arm stands up: little shoulder torque
STRETCHED = Pose(angles=[0.0, -5.0, 0.0, -90.0, -90.0, 0.0])  # reaching out level: the most shoulder torque
SHOULDER = 1


def _hold(sim: SimController, clock: FakeClock, pose: Pose) -> None:
    sim.set_pose(pose, MotionParams(speed=100))
    finish(sim, clock, step=0.1)


def test_six_records_that_agree_with_the_pose(sim: SimController) -> None:
    motors = sim.get_motors()
    assert len(motors) == 6
    angles = sim.get_pose().angles
    for motor, angle in zip(motors, angles, strict=True):
        assert motor.angle == pytest.approx(angle) and motor.positionFeedback == pytest.approx(angle)
        assert motor.positionSetpoint - motor.positionFeedback == pytest.approx(motor.positionError)
        assert abs(motor.positionError) < 0.1
        assert 47.0 < motor.voltage <= 48.0
        assert motor.rotorVelocity == 0.0 and motor.velocityFeedback == 0.0
        assert 20.0 <= motor.statorTemperature <= 40.0


def test_currents_rise_with_the_load(sim: SimController, clock: FakeClock) -> None:
    _hold(sim, clock, UPRIGHT)
    light = sim.get_motors()[SHOULDER]
    _hold(sim, clock, STRETCHED)
    heavy = sim.get_motors()[SHOULDER]
    assert heavy.phaseCurrent > 3 * light.phaseCurrent
    assert heavy.rmsCurrent > 3 * light.rmsCurrent
    assert sim.get_motors()[SHOULDER].voltage < 48.0


def test_a_moving_joint_reports_rotor_speed_through_its_gear(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(Pose(angles=[60.0, -90.0, 90.0, -90.0, -90.0, 0.0]), MotionParams(speed=50))
    clock.advance(0.5)  # cruising by now
    base = sim.get_motors()[0]
    before = sim.get_pose().angles[0]
    clock.advance(0.01)
    joint_deg_s = (sim.get_pose().angles[0] - before) / 0.01
    assert base.rotorVelocity == pytest.approx(joint_deg_s / 6.0 * 101.0, rel=0.01)  # deg/s -> RPM x gear
    assert base.velocityFeedback == base.rotorVelocity
    assert 0.0 < base.positionError < 0.1  # the setpoint runs a little ahead
    assert base.phaseCurrent > 0.1  # friction and inertia
    assert sim.get_motors()[0].rotorVelocity > 0


def test_temperatures_rise_under_load_and_settle(sim: SimController, clock: FakeClock) -> None:
    _hold(sim, clock, STRETCHED)
    start = sim.get_motors()[SHOULDER].statorTemperature
    clock.advance(300.0)
    warmer = sim.get_motors()[SHOULDER].statorTemperature
    clock.advance(3000.0)
    hot = sim.get_motors()[SHOULDER].statorTemperature
    clock.advance(3000.0)
    settled = sim.get_motors()[SHOULDER].statorTemperature
    assert start < warmer < hot
    assert settled - hot < 0.01 * (hot - start)
    assert sim.get_motors()[SHOULDER].servoTemperature > 25.0


def test_temperatures_depend_on_history_not_on_how_often_they_are_read(clock: FakeClock) -> None:
    often, rarely = SimController("pulse75", clock), SimController("pulse75", clock)
    for sim in (often, rarely):
        sim.set_pose(STRETCHED, MotionParams(speed=30))
        sim.set_pose(UPRIGHT, MotionParams(speed=30))
        sim.set_pose(STRETCHED, MotionParams(speed=30))
    for _ in range(200):
        clock.advance(0.37)
        often.get_motors()
    a = np.array([m.statorTemperature for m in often.get_motors()])
    b = np.array([m.statorTemperature for m in rarely.get_motors()])
    assert np.allclose(a, b, atol=0.01)
    assert np.max(a) > 25.1


def test_the_robot_id_is_stable_and_per_model(
    sim: SimController, sim90: SimController, clock: FakeClock
) -> None:
    robot_id = sim.get_robot_id()
    assert robot_id.isalnum() and len(robot_id) == 18
    assert SimController("pulse75", clock).get_robot_id() == robot_id
    assert sim90.get_robot_id() != robot_id
