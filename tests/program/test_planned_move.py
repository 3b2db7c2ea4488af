"""A planned Move J step: its path around the cell's obstacles is found when the step runs (from where the arm
is, in the cell as it is then) and run as one blended /poses/run; the same step unplanned is refused naming
the obstacle. Files stay as they were for programs without planned moves."""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
import pytest
from pydantic import ValidationError

from pendant.controller import Controller, MotionParams, MotionType, Pose, Position
from pendant.kinematics import ArmModel
from pendant.planning.joint_planner import MSG_CANCELLED, PlanCancelled
from pendant.planning.live import ControllerPlanner
from pendant.planning.scenes import BOX
from pendant.program import MoveStep, ProgramRunner, RunState, Waypoint
from pendant.program.blended import run_planned_path
from pendant.program.files import dump_program, parse_program
from pendant.program.motion import MSG_NO_PLANNER
from pendant.sim import FakeClock, SimController
from tests.support.programs import POLL_S, move, program_of, settle, teach

ANGLE_TOL_DEG = 0.5  # the runner's own arrival tolerance
SEARCH_POLLS_BEFORE_STOP = 1  # the search has begun: its first look at the run's stop


@pytest.fixture
def beyond(sim: SimController, clock: FakeClock) -> Waypoint:
    """A waypoint at J1 +60 degrees taught before the box went up; the arm then at J1 -60, the box between."""
    waypoint = teach(sim, clock, BOX.target_deg, "beyond")
    sim.set_pose(Pose(angles=list(BOX.start_deg)), MotionParams(speed=100.0))
    settle(sim, clock)
    sim.add_obstacle(BOX.obstacles[0])
    return waypoint


def _runner(sim: SimController, clock: FakeClock, *, planner: bool = True) -> ProgramRunner:
    plans = ControllerPlanner(ArmModel.load("pulse75")) if planner else None
    return ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S, planner=plans)


def test_a_planned_move_j_goes_around_the_box_where_the_unplanned_one_is_refused_naming_it(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    refused = _runner(sim, clock).run(program_of(move(beyond, speed=100.0)))
    assert refused.state is RunState.FAILED
    assert "Collision" in refused.message and "'box'" in refused.message, refused.message
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)  # refused: nothing moved

    done = _runner(sim, clock).run(program_of(move(beyond, speed=100.0, planned=True)))
    assert done.state is RunState.FINISHED, done.message
    assert np.allclose(sim.get_pose().angles, BOX.target_deg, atol=ANGLE_TOL_DEG)


CORNER_PATH_DEG = (
    (0.0, -90.0, 90.0, -90.0, -90.0, 0.0),
    (40.0, -90.0, 90.0, -90.0, -90.0, 0.0),
    (40.0, -60.0, 60.0, -90.0, -90.0, 0.0),
)  # a right-angle corner in joint space
ON_SEGMENTS_TOL_DEG = 0.05


def _farthest_off_the_segments(sim: SimController, clock: FakeClock, send: Callable[[], None]) -> float:
    """Runs `send` on the simulator at CORNER_PATH_DEG[0] and follows the arm on the fake clock: the largest
    distance (degrees, per joint) of any configuration it passes from the polyline through CORNER_PATH_DEG."""
    sim.set_pose(Pose(angles=list(CORNER_PATH_DEG[0])), MotionParams(speed=100.0))
    settle(sim, clock)
    send()
    dense = np.concatenate([np.linspace(a, b, 2001) for a, b in itertools.pairwise(CORNER_PATH_DEG)])
    farthest = 0.0
    while clock.now() < sim.busy_until():
        clock.advance(0.01)
        here = np.array(sim.get_pose().angles)
        farthest = max(farthest, float(np.min(np.max(np.abs(dense - here), axis=1))))
    assert np.allclose(sim.get_pose().angles, CORNER_PATH_DEG[-1], atol=ANGLE_TOL_DEG)
    return farthest


def test_a_planned_path_is_run_along_the_segments_the_planner_checked_not_a_spline_that_bulges_off(
    sim: SimController, clock: FakeClock
) -> None:
    """The planner checks straight joint segments against the cell; a SPLINE through the same waypoints
    (what /poses/run gives) cuts the corner by degrees, into what the path went around (a CI failure:
    the simulator refused a planned path with "Collision detected")."""
    poses = [Pose(angles=list(angles)) for angles in CORNER_PATH_DEG[1:]]
    planned = _farthest_off_the_segments(sim, clock, lambda: run_planned_path(sim, poses, 50.0))
    spline = _farthest_off_the_segments(
        sim, clock, lambda: sim.run_poses(poses, MotionParams(speed=50.0, motion_type=MotionType.JOINT))
    )
    assert planned <= ON_SEGMENTS_TOL_DEG, f"{planned:.3f} deg off the checked segments"
    assert spline > 10 * ON_SEGMENTS_TOL_DEG, (
        f"the spline stayed within {spline:.3f} deg: the measure is blind"
    )


def test_a_planned_move_to_a_waypoint_inside_the_box_fails_saying_so_and_nothing_moves(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    inside = Waypoint(name="inside", pose=Pose(angles=[0.0, *BOX.start_deg[1:]]), position=beyond.position)
    result = _runner(sim, clock).run(program_of(move(inside, planned=True)))
    assert result.state is RunState.FAILED
    assert "the target itself is inside 'box'" in result.message, result.message
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)


def test_without_a_planner_a_planned_step_fails_saying_so(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    result = _runner(sim, clock, planner=False).run(program_of(move(beyond, planned=True)))
    assert result.state is RunState.FAILED
    assert MSG_NO_PLANNER in result.message
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)


def test_the_flag_is_saved_only_when_set_and_a_file_without_it_loads_unplanned(beyond: Waypoint) -> None:
    unplanned = program_of(move(beyond))
    assert b"planned" not in dump_program(unplanned)  # as an older pendant saved it, and can open it
    planned = program_of(move(beyond, planned=True))
    loaded = parse_program(dump_program(planned), "planned.json")
    step = loaded.steps[0]
    assert isinstance(step, MoveStep) and step.planned
    again = parse_program(dump_program(unplanned), "unplanned.json").steps[0]
    assert isinstance(again, MoveStep) and not again.planned
    with pytest.raises(ValidationError, match="only a Move J can be planned"):
        MoveStep(waypoint="beyond", motion=MotionType.LINEAR, planned=True)


def test_stop_while_the_path_is_searched_ends_the_search_and_nothing_moves(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    # The operator presses Stop while the planned step is still searching its path round the box: the
    # search ends there (it polls the run's stop), the run says stopped, and no path is sent afterwards.
    plans = ControllerPlanner(ArmModel.load("pulse75"), budget_s=10.0)  # long enough to be under way
    polls_after_stop: list[int] = []
    ended_by: list[str] = []

    def planner(controller: Controller, goal: Pose | Position, cancelled: Callable[[], bool]) -> list[Pose]:
        polls = 0

        def polled() -> bool:
            nonlocal polls
            polls += 1
            if polls == SEARCH_POLLS_BEFORE_STOP:
                runner.stop()  # the Stop button, pressed while the search runs
            if polls > SEARCH_POLLS_BEFORE_STOP:
                polls_after_stop.append(polls)
            return cancelled()

        try:
            return plans(controller, goal, polled)
        except PlanCancelled as cancel:
            ended_by.append(cancel.message)
            raise

    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S, planner=planner)
    result = runner.run(program_of(move(beyond, speed=100.0, planned=True)))
    assert result.state is RunState.STOPPED, result.message
    assert ended_by == [MSG_CANCELLED], "the search ran on after the stop"
    assert len(polls_after_stop) <= 2, "the search did not end at the first poll after the stop"
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)  # nothing moved
    clock.advance(2.0)
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)  # and nothing was sent later


def test_a_freeze_heard_while_a_planned_move_searches_ends_the_run_with_its_cause(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    """Not the program's Stop: a Freeze from elsewhere, heard while the path is being searched."""
    plans = ControllerPlanner(ArmModel.load("pulse75"))
    holder: list[ProgramRunner] = []

    def planner(controller: Controller, goal: Pose | Position, cancelled: Callable[[], bool]) -> list[Pose]:
        holder[0].stop_heard("Freeze from the API (127.0.0.1)")
        sim.freeze()
        return plans(controller, goal, cancelled)

    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S, planner=planner)
    holder.append(runner)
    result = runner.run(program_of(move(beyond, speed=100.0, planned=True)))

    assert result.state is RunState.STOPPED, result.message
    assert result.message == "Stopped at step 1 by Freeze from the API (127.0.0.1)"
    clock.advance(2.0)
    assert np.allclose(sim.get_pose().angles, BOX.start_deg, atol=1e-6)  # the path was never sent
    assert runner.can_resume


def test_a_freeze_heard_during_a_planned_moves_motion_ends_the_run_there(
    sim: SimController, clock: FakeClock, beyond: Waypoint
) -> None:
    """Seen in the page before: the arm stopped for a moment, then the run carried on to "Finished"."""
    holder: list[ProgramRunner] = []
    started: list[float] = []

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if sim.get_motion_status().value == "RUNNING" and not started:
            started.append(clock.now())
        if started and clock.now() - started[0] >= 0.5 and holder[0].progress.state is RunState.RUNNING:
            holder[0].stop_heard("Freeze by Tab 2")
            sim.freeze()

    plans = ControllerPlanner(ArmModel.load("pulse75"))
    runner = ProgramRunner(sim, sleep=sleep, now=clock.now, poll_s=POLL_S, planner=plans)
    holder.append(runner)
    result = runner.run(program_of(move(beyond, speed=100.0, planned=True)))

    assert result.state is RunState.STOPPED, result.message
    assert result.message == "Stopped at step 1 by Freeze by Tab 2"
    held = np.array(sim.get_pose().angles)
    clock.advance(3.0)
    np.testing.assert_allclose(sim.get_pose().angles, held, atol=1e-6)
    assert not np.allclose(held, BOX.target_deg, atol=ANGLE_TOL_DEG)
