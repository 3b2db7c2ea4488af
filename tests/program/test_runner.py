"""The runner on the simulator's fake clock: blending, loops, step, pause, stop, errors and waits."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller import MotionType, Pose, SignalLevel
from pendant.program import (
    GripperAction,
    GripperStep,
    OutputStep,
    ProgramRunner,
    RunState,
    WaitInputStep,
    WaitStep,
    Waypoint,
    compile_program,
)
from pendant.program.plan import MoveGroup, Node
from pendant.sim import FakeClock, SimController
from tests.support.programs import ANGLE_TOL_DEG, Recording, angles, move, program_of, sleeping


def test_consecutive_moves_of_one_type_and_speed_run_as_one_blended_call(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    program = program_of(
        move(a),
        move(b),  # JOINT 50: one /poses/run
        move(c, MotionType.LINEAR),
        move(a, MotionType.LINEAR),  # LINEAR 50: one /positions/run
        move(b, speed=80.0),  # another speed: its own call
        OutputStep(port=1, level=SignalLevel.HIGH),
        move(c),
    )
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)

    result = runner.run(program)

    assert result.state is RunState.FINISHED and result.progress == 1.0
    assert recording.names() == ["run_poses", "run_positions", "run_poses", "set_output", "run_poses"]
    first_poses, params = recording.calls[0][1]
    assert [p.angles for p in first_poses] == [a.pose.angles, b.pose.angles]
    assert params.motion_type is MotionType.JOINT and params.speed == 50.0
    assert len(recording.calls[1][1][0]) == 2
    np.testing.assert_allclose(angles(sim), c.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.HIGH


def test_plan_groups_only_neighbouring_moves_and_step_mode_splits_them(
    waypoints: dict[str, Waypoint],
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    program = program_of(move(a), move(b), WaitStep(ms=10), move(a), move(b, MotionType.LINEAR))
    assert [_lines(n) for n in compile_program(program)] == [[0, 1], [2], [3], [4]]
    assert [_lines(n) for n in compile_program(program, blend=False)] == [[0], [1], [2], [3], [4]]


def _lines(node: Node) -> list[int]:
    return [t.line for t in node.targets] if isinstance(node, MoveGroup) else [node.line]


def test_outputs_are_set_only_once_the_arm_has_arrived(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    seen: list[np.ndarray] = []
    recording = Recording(sim)

    def set_output(port: int, level: SignalLevel) -> None:
        seen.append(angles(sim))
        sim.set_output(port, level)

    recording.answer("set_output", set_output)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    runner.run(program_of(move(a), OutputStep(port=2, level=SignalLevel.HIGH)))
    np.testing.assert_allclose(seen[0], a.pose.angles, atol=ANGLE_TOL_DEG)


def test_loop_count_repeats_the_whole_program(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(
        move(waypoints["A"]),
        GripperStep(action=GripperAction.CLOSE, timeout_ms=100),
        move(waypoints["B"]),
        GripperStep(action=GripperAction.OPEN, timeout_ms=100),
    )
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    progress: list[float] = []
    runner.add_listener(lambda p: progress.append(p.progress))

    result = runner.run(program, loops=3)

    assert result.state is RunState.FINISHED and result.loop == 3
    assert recording.names() == ["run_poses", "close_gripper", "run_poses", "open_gripper"] * 3
    assert progress == sorted(progress) and progress[-1] == 1.0


def test_step_runs_one_step_at_a_time_without_blending(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    program = program_of(move(a), move(b), OutputStep(port=1, level=SignalLevel.HIGH))
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)

    first = runner.step(program)
    assert first.state is RunState.PAUSED and first.step_index == 1
    np.testing.assert_allclose(angles(sim), a.pose.angles, atol=ANGLE_TOL_DEG)
    second = runner.step()
    assert second.state is RunState.PAUSED and second.step_index == 2
    np.testing.assert_allclose(angles(sim), b.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.LOW
    assert runner.step().state is RunState.FINISHED
    assert sim.get_output(1) is SignalLevel.HIGH


def test_a_refused_move_stops_the_program_naming_the_step_and_the_reason(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    beyond_limits = Waypoint(
        name="Far", pose=Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0]), position=a.position
    )
    program = program_of(
        move(a),
        OutputStep(port=1, level=SignalLevel.HIGH),
        move(beyond_limits),
        OutputStep(port=2, level=SignalLevel.HIGH),
    )
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)

    result = runner.run(program)

    assert result.state is RunState.FAILED and result.failed_step == 2
    assert result.message == "Step 3 (Move J to Far @ 50%) failed: Unreachable Pose"
    assert sim.get_output(1) is SignalLevel.HIGH and sim.get_output(2) is SignalLevel.LOW


def test_a_refused_blended_run_names_every_step_it_covers_and_moves_nothing(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    far = Waypoint(name="Far", pose=Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0]), position=a.position)
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    before = angles(sim)

    result = runner.run(program_of(move(a), move(b), move(far)))

    assert result.state is RunState.FAILED and result.failed_step == 0
    assert result.message == "Steps 1-3 (blended moves to A, B, Far) failed: Unreachable Pose"
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)


def test_a_fault_during_a_motion_names_the_step_it_interrupted(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    from pendant.sim.controller import Fault

    program = program_of(WaitStep(ms=100), move(waypoints["A"]))
    runner = ProgramRunner(
        sim,
        now=clock.now,
        sleep=sleeping(clock, clock.now() + 0.5, lambda: sim.inject_fault(Fault.EMERGENCY)),
    )

    result = runner.run(program)

    # The emergency is the controller's own stop (issue 31): said as a stop, at the step it interrupted.
    assert result.state is RunState.STOPPED and result.failed_step == 1
    assert result.message == "Stopped at step 2 by the controller (EMERGENCY)"


def test_wait_for_input_times_out_with_a_clear_message(sim: SimController, clock: FakeClock) -> None:
    program = program_of(
        WaitInputStep(port=2, level=SignalLevel.HIGH, timeout_ms=1500),
    )
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    started = clock.now()

    result = runner.run(program)

    assert result.state is RunState.FAILED
    assert (
        result.message
        == "Step 1 (Wait DI2 HIGH (timeout 1500 ms)) failed: DI2 did not go HIGH within 1500 ms"
    )
    assert clock.now() - started == pytest.approx(1.5, abs=0.06)


def test_wait_for_input_continues_when_the_input_arrives(sim: SimController, clock: FakeClock) -> None:
    program = program_of(
        WaitInputStep(port=3, level=SignalLevel.HIGH, timeout_ms=5000),
        OutputStep(port=1, level=SignalLevel.HIGH),
    )
    runner = ProgramRunner(
        sim, now=clock.now, sleep=sleeping(clock, 0.3, lambda: sim.set_input(3, SignalLevel.HIGH))
    )
    assert runner.run(program).state is RunState.FINISHED
    assert sim.get_output(1) is SignalLevel.HIGH


def test_waits_and_the_gripper_take_their_time(sim: SimController, clock: FakeClock) -> None:
    program = program_of(WaitStep(ms=750), GripperStep(action=GripperAction.CLOSE, timeout_ms=500))
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    started = clock.now()
    runner.run(program)
    assert clock.now() - started == pytest.approx(1.25, abs=0.06)
    assert sim.gripper_opening() == 0.0


def test_loops_zero_repeats_until_stop(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(move(waypoints["A"]), move(waypoints["B"], speed=80.0))
    holder: list[ProgramRunner] = []
    runner = ProgramRunner(sim, now=clock.now, sleep=sleeping(clock, 30.0, lambda: holder[0].stop()))
    holder.append(runner)
    result = runner.run(program, loops=0)
    assert result.state is RunState.STOPPED and result.loop > 2
