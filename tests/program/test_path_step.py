"""Path steps: a hand-drawn curve recorded in free drive becomes one step, which plays back as one blended
`/run/linear/positions` run within the recording's tolerance, on the simulator and over HTTP, stop-and-go on
a controller without /run/* (404), resuming at the waypoint it was heading for after a pause; and
BlendedRun as the runner's BlendedPath for taught moves; a freeze mid-path, retried."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller import Controller, Pose, Position, SignalLevel
from pendant.controller.types import Point, Rotation
from pendant.kinematics.transforms import position_to_matrix
from pendant.program import (
    PathStep,
    Program,
    ProgramRunner,
    ProgramWorkspace,
    RunState,
    WaitStep,
    Waypoint,
    compile_program,
    describe_step,
)
from pendant.program.blended import FALLBACK_NOTE, BlendedRun
from pendant.program.files import MAX_FILE_BYTES, dump_program, parse_program
from pendant.program.limits import (
    MAX_PATH_POINTS,
    MAX_PROGRAM_PATH_POINTS,
    MAX_STEPS,
    PROGRAM_NAME_MAX,
    WAYPOINT_NAME_MAX,
)
from pendant.program.models import OutputAction, PathPoint
from pendant.program.plan import MoveGroup
from pendant.remote import RemoteController
from pendant.sim import FakeClock, SimController
from pendant.teach.path_step import path_step
from pendant.teach.recording import Recording
from tests.support.deviation import from_rest_at, max_deviation_mm, max_turn_deg, start_index
from tests.support.path_playback import Sampler, WithoutRunOperations, hand_drawn_s, recorded_points
from tests.support.programs import Recording as CallLog
from tests.support.programs import many_moves, move, program_of

TOL_MM = 1.0
TOL_DEG = 1.0
END_TOL_M = 1e-6
ANGLE_TOL_DEG = 1e-6
STOP_TOL_M = 1e-6
STOPPING = 0.1  # of the median distance between samples: the arm is all but still


@pytest.fixture
def recording(sim: SimController, clock: FakeClock) -> Recording:
    return hand_drawn_s(sim, clock)


@pytest.fixture
def step(recording: Recording) -> PathStep:
    return path_step(recording, TOL_MM, TOL_DEG, "s1")


def test_a_recording_becomes_one_step_that_compiles_to_an_approach_and_one_blended_run(
    recording: Recording, step: PathStep
) -> None:
    assert 2 < len(step.points) <= 100 and len(step.points) < len(recording.samples) / 2
    assert (step.tol_mm, step.tol_deg, step.blend_mm) == (TOL_MM, TOL_DEG, TOL_MM / 2)
    assert step.points[0].pose.angles == list(recording.samples[0].joints_deg)
    assert step.points[-1].position == recording.samples[-1].tcp
    assert describe_step(step) == f"Path s1: {len(step.points)} waypoints, 1 mm / 1° @ 100 mm/s"
    approach, run = compile_program(Program(steps=(step,)))
    assert isinstance(approach, MoveGroup) and approach.by_angles and not approach.path
    assert isinstance(run, MoveGroup) and run.path and len(run.targets) == len(step.points) - 1
    assert {t.blend_mm for t in run.targets} == {TOL_MM / 2}


def test_a_path_step_plays_as_one_blended_run_within_the_tolerance(
    sim: SimController, clock: FakeClock, recording: Recording, step: PathStep
) -> None:
    sampler = Sampler(sim, clock)
    log = CallLog(sim)
    runner = ProgramRunner(log, sleep=sampler, now=clock.now)

    result = runner.run(Program(steps=(step,)))

    assert result.state is RunState.FINISHED and result.notice == ""
    assert log.names() == ["run_poses", "run_linear_positions"]  # the approach, then the whole path
    positions, params = log.calls[1][1]
    assert len(positions) == len(step.points) - 1 and params.interpolationType.value == "BLEND"
    assert {p.blend for p in positions} == {TOL_MM / 2 / 1000.0}
    recorded = recorded_points(recording)
    start = start_index(sampler.played, recorded[0])
    played = sampler.played[start:]
    there, back = max_deviation_mm(recorded, played)
    assert there <= TOL_MM and back <= TOL_MM, (there, back)
    recorded_poses = np.array([position_to_matrix(s.tcp) for s in recording.samples])
    turned = max_turn_deg(recorded_poses, np.array(sampler.poses[start:]))
    assert turned <= TOL_DEG, turned
    np.testing.assert_allclose(played[-1], recorded[-1], atol=END_TOL_M)


def test_over_http_the_run_is_the_same(
    sim: SimController, clock: FakeClock, remote: RemoteController, recording: Recording, step: PathStep
) -> None:
    sampler = Sampler(sim, clock)
    result = ProgramRunner(remote, sleep=sampler, now=clock.now).run(Program(steps=(step,)))
    assert result.state is RunState.FINISHED and result.notice == ""
    recorded = recorded_points(recording)
    there, back = max_deviation_mm(recorded, from_rest_at(sampler.played, recorded[0]))
    assert there <= TOL_MM and back <= TOL_MM, (there, back)


def test_without_run_operations_the_path_plays_stop_and_go_and_says_so(
    sim: SimController, clock: FakeClock, recording: Recording, step: PathStep
) -> None:
    sampler = Sampler(sim, clock)
    with TestClient(WithoutRunOperations(create_app(sim))) as client:
        older: Controller = RemoteController("http://testserver", client=client)
        runner = ProgramRunner(older, sleep=sampler, now=clock.now)
        result = runner.run(Program(steps=(step,)))
    assert result.state is RunState.FINISHED and result.notice == FALLBACK_NOTE
    recorded = recorded_points(recording)
    played = from_rest_at(sampler.played, recorded[0])
    there, back = max_deviation_mm(recorded, played)
    # Straight segments between recorded samples, stopping at each: within the simplification's half.
    assert there <= TOL_MM / 2 and back <= TOL_MM / 2, (there, back)
    # It stopped at every waypoint: the TCP passes it, and slows to a standstill there.
    steps = np.linalg.norm(np.diff(played, axis=0), axis=1)
    cruising = float(np.median(steps))
    for point in step.points[1:-1]:
        p = point.position.point
        gap = np.linalg.norm(played - [p.x, p.y, p.z], axis=1)
        at = int(np.argmin(gap))
        assert gap[at] < STOP_TOL_M, f"never at {p}"
        assert min(steps[at - 1], steps[at]) < STOPPING * cruising, f"no stop at {p}"


def a_second_into_the_path(
    sampler: Sampler, log: CallLog, clock: FakeClock, action: Callable[[], None]
) -> None:
    """Do `action` at the runner's first sleep a second after the path's run was sent."""
    sent_at: list[float] = []

    def check() -> None:
        if "run_linear_positions" in log.names():
            sent_at.append(clock.now())
            if sent_at[-1] - sent_at[0] >= 1.0:
                action()
                return
        sampler.at = check

    sampler.at = check


def test_a_paused_path_resumes_at_the_waypoint_it_was_heading_for(
    sim: SimController, clock: FakeClock, recording: Recording, step: PathStep
) -> None:
    sampler = Sampler(sim, clock)
    log = CallLog(sim)
    runner = ProgramRunner(log, sleep=sampler, now=clock.now)
    program = Program(steps=(step,))
    a_second_into_the_path(sampler, log, clock, runner.pause)
    paused = runner.run(program)
    assert paused.state is RunState.PAUSED
    heading = runner.resume_target
    assert heading is not None and 1 <= heading < len(step.points) - 1
    stopped_at = sim.get_position()

    resumed = runner.resume()

    assert resumed.state is RunState.FINISHED
    _, second_run = (args for name, args in log.calls if name == "run_linear_positions")
    # The second request starts at the waypoint the arm was heading for (targets are points[1:]).
    second_positions = second_run[0]
    assert second_positions[0].point == step.points[heading + 1].position.point
    assert len(second_positions) == len(step.points) - 1 - heading
    assert stopped_at != sim.get_position()
    recorded = recorded_points(recording)
    there, back = max_deviation_mm(recorded, from_rest_at(sampler.played, recorded[0]))
    assert there <= TOL_MM and back <= TOL_MM, (there, back)


def test_a_path_step_is_saved_and_read_back_and_programs_hold_a_bounded_number_of_points(
    step: PathStep, waypoints: dict[str, Waypoint], make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    program = Program(name="drawn", steps=(step,))
    saved = dump_program(program)
    read = parse_program(saved, "drawn.json")
    assert dump_program(read) == saved and isinstance(read.steps[0], PathStep)
    assert read.steps[0].points[0].pose == step.points[0].pose

    # The largest program: full paths (every number at full precision) up to the limit, long moves after.
    rng = np.random.default_rng(7)
    noisy = tuple(
        PathPoint(
            pose=Pose(angles=list(rng.uniform(-300.0, 300.0, 6))),
            position=Position(
                point=Point(**dict(zip("xyz", rng.uniform(-1.0, 1.0, 3), strict=True))),
                rotation=Rotation(
                    **dict(zip(("roll", "pitch", "yaw"), rng.uniform(-3.0, 3.0, 3), strict=True))
                ),
            ),
        )
        for _ in range(MAX_PATH_POINTS)
    )
    paths = MAX_PROGRAM_PATH_POINTS // MAX_PATH_POINTS
    full = PathStep(name="p" * WAYPOINT_NAME_MAX, points=noisy)
    moves = many_moves(waypoints["C"], MAX_STEPS - paths, name="n" * PROGRAM_NAME_MAX)
    largest = moves.model_copy(update={"steps": (*([full] * paths), *moves.steps)})
    assert len(dump_program(largest)) <= MAX_FILE_BYTES
    workspace = make_workspace()
    workspace.upload("largest.json", dump_program(largest))
    make_workspace().load(workspace.save_as("largest"))  # a restarted pendant reads it back
    with pytest.raises(ValueError, match=f"at most {MAX_PROGRAM_PATH_POINTS} points"):
        Program(steps=(full,) * (paths + 1))


def test_step_goes_to_the_start_then_plays_the_whole_path(
    sim: SimController, clock: FakeClock, step: PathStep
) -> None:
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    program = Program(steps=(step, WaitStep(ms=10)))
    first = runner.step(program)
    assert first.state is RunState.PAUSED and first.step_index == 0
    assert sim.get_pose().angles == pytest.approx(step.points[0].pose.angles, abs=ANGLE_TOL_DEG)
    second = runner.step()
    assert second.state is RunState.PAUSED and second.step_index == 1
    end = step.points[-1].position.point
    here = sim.get_position().point
    assert np.allclose([here.x, here.y, here.z], [end.x, end.y, end.z], atol=END_TOL_M)


def test_as_the_runners_blended_path_it_runs_taught_moves_with_their_actions_in_one_request(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    log = CallLog(sim)
    runner = ProgramRunner(log, sleep=clock.advance, now=clock.now, blended=BlendedRun(log))
    set_do1 = (OutputAction(port=1, value=SignalLevel.HIGH),)
    program = program_of(move(waypoints["A"], actions=set_do1), move(waypoints["B"]), move(waypoints["C"]))
    result = runner.run(program)
    assert result.state is RunState.FINISHED
    assert log.names() == ["run_joint_poses"]  # the action no longer ends the blend: one request
    poses, _ = log.calls[0][1]
    assert [p.angles for p in poses] == [waypoints[n].pose.angles for n in "ABC"]
    assert poses[0].actions[0].port == 1 and sim.get_output(1) is SignalLevel.HIGH
    assert sim.get_pose().angles == pytest.approx(waypoints["C"].pose.angles, abs=ANGLE_TOL_DEG)


def test_a_freeze_mid_path_fails_the_step_and_retry_finishes_it_from_where_it_was_heading(
    sim: SimController, clock: FakeClock, recording: Recording, step: PathStep
) -> None:
    sampler = Sampler(sim, clock)
    log = CallLog(sim)
    runner = ProgramRunner(log, sleep=sampler, now=clock.now)
    a_second_into_the_path(sampler, log, clock, sim.freeze)  # as Freeze on the page or PUT /freeze would
    failed = runner.run(Program(steps=(step,)))
    assert failed.state is RunState.FAILED and failed.failed_step == 0
    assert "Step 1 (Path s1" in failed.message and "the arm stopped before reaching s1[" in failed.message

    finished = runner.resume()

    assert finished.state is RunState.FINISHED
    assert log.names().count("run_poses") == 1  # not back to the start: on from where it was heading
    recorded = recorded_points(recording)
    there, back = max_deviation_mm(recorded, from_rest_at(sampler.played, recorded[0]))
    assert there <= TOL_MM and back <= TOL_MM, (there, back)
