"""The pre-flight on a twin of the embedded simulator: inputs assumed, loops, refusals in words."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.types import MotionParams, MotionType, Point, Pose, Position, Rotation, SignalLevel
from pendant.planning.clearance import Clearance
from pendant.planning.preflight import PreflightRefused, preflight
from pendant.planning.twin import TwinSeed, read_seed
from pendant.program import Step, Waypoint
from pendant.program.models import (
    CallStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    OutputStep,
    Program,
    WaitInputStep,
)
from pendant.sim import HOME_POSE_DEG, FakeClock, SimController
from tests.support.preflight_scene import LEFT_DEG, RIGHT_DEG, box_in_the_way, waypoint

HIGH, LOW = SignalLevel.HIGH, SignalLevel.LOW


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def arm(clock: FakeClock) -> SimController:
    return SimController(clock=clock)


def program(*steps: Step, extra: tuple[Waypoint, ...] = ()) -> Program:
    points = (waypoint("left", LEFT_DEG), waypoint("right", RIGHT_DEG), *extra)
    return Program(name="t", waypoints=points, steps=steps)


def test_an_if_follows_the_input_as_the_arm_reads_it_unless_one_is_given(arm: SimController) -> None:
    branching = program(
        IfStep(port=1, level=HIGH, then=(MoveStep(waypoint="left"),), otherwise=(MoveStep(waypoint="right"),))
    )
    as_read = preflight(branching, read_seed(arm))  # the arm's DI1 reads LOW
    assert as_read.ok
    assert as_read.assumed_inputs[1].level is LOW and as_read.assumed_inputs[1].why == "read from the arm"
    then_step, else_step = as_read.steps[1], as_read.steps[2]
    assert not then_step.checked and then_step.note == "not run with the inputs assumed"
    assert else_step.checked and else_step.duration_s > 0

    given = preflight(branching, read_seed(arm), inputs={1: HIGH})
    assert given.assumed_inputs[1].why == "given"
    assert given.steps[1].checked and not given.steps[2].checked


def test_a_wait_for_input_is_assumed_met_unless_the_input_is_given_otherwise(arm: SimController) -> None:
    waiting = program(WaitInputStep(port=2, level=HIGH, timeout_ms=1000), MoveStep(waypoint="left"))
    met = preflight(waiting, read_seed(arm))
    assert met.ok and met.assumed_inputs[2].why == "the wait's level"

    timed_out = preflight(waiting, read_seed(arm), inputs={2: LOW})
    assert not timed_out.ok
    assert timed_out.first_failure is not None and timed_out.first_failure.line == 1
    assert "DI2 did not go HIGH within 1000 ms" in timed_out.first_failure.reason
    assert timed_out.steps[0].duration_s == pytest.approx(1.0, abs=0.06)  # it waited out its timeout


def test_a_while_loop_runs_the_passes_assumed(arm: SimController) -> None:
    # (different speeds: two moves, not one blended group whose time the runner gives its first step)
    body = (MoveStep(waypoint="left", speed=30.0), MoveStep(waypoint="right", speed=40.0))
    looping = program(LoopStep(mode=LoopMode.WHILE, port=3, level=HIGH, body=body))
    once = preflight(looping, read_seed(arm))
    thrice = preflight(looping, read_seed(arm), loop_passes=3)
    assert once.ok and thrice.ok and thrice.loop_passes == 3
    # Every pass swings from left to right: three passes, three times that step's time.
    swing = once.steps[2].duration_s
    assert thrice.steps[2].duration_s == pytest.approx(3 * swing, rel=0.02)
    assert thrice.cycle_time_s > once.cycle_time_s + 2 * swing


def test_a_target_out_of_reach_is_said_in_words(arm: SimController) -> None:
    far = Position(point=Point(x=2.0, y=0.0, z=0.5), rotation=Rotation(roll=3.14159, pitch=0.0, yaw=0.0))
    reaching = program(
        MoveStep(waypoint="left"),
        MoveStep(waypoint="far", motion=MotionType.LINEAR),
        extra=(waypoint("far", HOME_POSE_DEG).model_copy(update={"position": far}),),
    )
    report = preflight(reaching, read_seed(arm))
    assert report.first_failure is not None and report.first_failure.line == 2
    assert "out of the arm's reach" in report.first_failure.reason


def test_a_joint_limit_is_named(arm: SimController) -> None:
    past = (*HOME_POSE_DEG[:5], 400.0)
    report = preflight(
        program(MoveStep(waypoint="twisted"), extra=(waypoint("twisted", past),)), read_seed(arm)
    )
    assert report.first_failure is not None
    assert report.first_failure.reason.startswith("J6 would go past its limit")


def test_clearance_and_peak_speed_per_step_and_the_arm_left_as_it_was(
    arm: SimController, clock: FakeClock
) -> None:
    arm.set_pose(Pose(angles=list(LEFT_DEG)), MotionParams(speed=100.0))
    clock.advance(10.0)
    seed = read_seed(arm).with_cell([box_in_the_way()], None)
    before = (arm.get_pose(), arm.get_obstacles(), arm.get_output(1))
    nearer = (20.0, *LEFT_DEG[1:])  # halfway to the box, J1 alone at 30 %: 36 degrees/s at most
    report = preflight(
        program(MoveStep(waypoint="nearer", speed=30.0), extra=(waypoint("nearer", nearer),)), seed
    )
    assert report.ok
    move = report.steps[0]
    assert move.closest_obstacle == "fixture" and move.min_clearance_mm is not None
    assert 0 < move.min_clearance_mm < report_clearance_at_start(arm, seed)
    assert move.peak_joint == 1 and move.peak_joint_speed_deg_s == pytest.approx(0.3 * 120.0, rel=0.02)
    assert (arm.get_pose(), arm.get_obstacles(), arm.get_output(1)) == before


def report_clearance_at_start(arm: SimController, seed: TwinSeed) -> float:
    """How far the arm is from the cell where it stands (the move goes nearer)."""
    clearance = Clearance(arm.arm, list(seed.obstacles), seed.tool_shape, seed.tool)
    closest = clearance(np.radians(LEFT_DEG))
    assert closest is not None
    return closest.mm


def test_a_program_that_calls_a_missing_one_is_refused(arm: SimController) -> None:
    def load(name: str) -> Program:
        raise FileNotFoundError(f"No program named {name!r}")

    with pytest.raises(PreflightRefused, match="Call gone"):
        preflight(
            program(CallStep(program="gone"), OutputStep(port=1, level=HIGH)), read_seed(arm), load=load
        )
    assert arm.get_output(1) is LOW  # nothing was run anywhere
