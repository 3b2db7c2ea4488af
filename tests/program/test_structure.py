"""Program structure on the simulator's fake clock: loops (times, while, until a DI), If/Else, relative moves,
waypoint actions, pallets, called programs, run from a line and resume a failed run at the failed step."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from pendant.controller import MotionType, NotResponding, Pose, SignalLevel
from pendant.kinematics.transforms import position_to_matrix
from pendant.program import (
    CallStep,
    CommentStep,
    Frame,
    GripperAction,
    GripperAtWaypoint,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    Offset,
    OutputAction,
    OutputStep,
    PalletStep,
    PlanError,
    ProgramRunner,
    ProgramStore,
    RunState,
    WaitInputStep,
    Waypoint,
    compile_program,
)
from pendant.program.geometry import pallet_cells
from pendant.program.plan import MoveGroup
from pendant.sim import FakeClock, SimController
from tests.support.programs import ANGLE_TOL_DEG, Recording, angles, move, program_of, sleeping

POSITION_TOL_M = 0.002  # the runner's arrival tolerance for TCP targets


def tcp(sim: SimController) -> np.ndarray:
    p = sim.get_position().point
    return np.array([p.x, p.y, p.z])


def point(waypoint: Waypoint) -> np.ndarray:
    p = waypoint.position.point
    return np.array([p.x, p.y, p.z])


def test_a_loop_repeats_its_body_n_times_and_comments_do_nothing(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    loop = LoopStep(
        times=3,
        body=(
            move(a).step,
            CommentStep(text="grip here"),
            GripperStep(action=GripperAction.CLOSE, timeout_ms=50),
            move(b).step,
        ),
    )
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    result = runner.run(program_of(loop, OutputStep(port=1, level=SignalLevel.HIGH), extra=(a, b)))
    assert result.state is RunState.FINISHED
    assert recording.names() == ["run_poses", "close_gripper", "run_poses"] * 3 + ["set_output"]


@pytest.mark.parametrize("mode", [LoopMode.UNTIL, LoopMode.WHILE])
def test_a_loop_on_an_input_stops_when_the_sensor_says_so(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint], mode: LoopMode
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    # until DI1 HIGH; while DI1 LOW: the same loop, said two ways
    level = SignalLevel.HIGH if mode is LoopMode.UNTIL else SignalLevel.LOW
    loop = LoopStep(mode=mode, port=1, level=level, body=(move(a).step, move(b).step))
    recording = Recording(sim)
    # The tray becomes empty (DI1 HIGH) after a few seconds of picking.
    runner = ProgramRunner(
        recording,
        now=clock.now,
        sleep=sleeping(clock, 4.0, lambda: sim.set_input(1, SignalLevel.HIGH)),
    )
    result = runner.run(program_of(loop, extra=(a, b)))
    assert result.state is RunState.FINISHED
    passes = recording.names().count("run_poses")
    assert passes >= 2  # it looped while the input said to, and then stopped
    np.testing.assert_allclose(angles(sim), b.pose.angles, atol=ANGLE_TOL_DEG)  # a whole pass, not half
    again = Recording(sim)
    ProgramRunner(again, sleep=clock.advance, now=clock.now).run(program_of(loop, extra=(a, b)))
    assert again.names() == []  # the condition is checked before the first pass too


def test_if_runs_then_or_else_by_the_input(sim: SimController, clock: FakeClock) -> None:
    branch = IfStep(
        port=2,
        level=SignalLevel.HIGH,
        then=(OutputStep(port=1, level=SignalLevel.HIGH),),
        otherwise=(OutputStep(port=2, level=SignalLevel.HIGH),),
    )
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    runner.run(program_of(branch))
    assert (sim.get_output(1), sim.get_output(2)) == (SignalLevel.LOW, SignalLevel.HIGH)
    sim.set_output(2, SignalLevel.LOW)
    sim.set_input(2, SignalLevel.HIGH)
    runner.run(program_of(branch))
    assert (sim.get_output(1), sim.get_output(2)) == (SignalLevel.HIGH, SignalLevel.LOW)


def test_relative_moves_go_to_the_offset_in_the_base_and_in_the_tool_frame(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    above = move(a, MotionType.LINEAR, offset=Offset(z=50.0))
    assert runner.run(program_of(move(a), above)).state is RunState.FINISHED
    np.testing.assert_allclose(tcp(sim), point(a) + np.array([0.0, 0.0, 0.05]), atol=POSITION_TOL_M)

    back = move(a, MotionType.LINEAR, offset=Offset(z=-30.0, frame=Frame.TOOL))
    assert runner.run(program_of(move(a), back)).state is RunState.FINISHED
    tool_z = position_to_matrix(a.position)[:3, 2]  # the tool's own z axis, in the base frame
    np.testing.assert_allclose(tcp(sim), point(a) - 0.03 * tool_z, atol=POSITION_TOL_M)


def test_a_waypoint_action_is_done_once_the_arm_is_there_and_ends_the_blend(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    seen: list[np.ndarray] = []
    recording = Recording(sim)

    def set_output(port: int, level: SignalLevel) -> None:
        seen.append(angles(sim))
        sim.set_output(port, level)

    recording.answer("set_output", set_output)
    at_a = move(
        a,
        actions=(OutputAction(port=1, value=SignalLevel.HIGH), GripperAtWaypoint(value=GripperAction.CLOSE)),
    )
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    assert runner.run(program_of(at_a, move(b))).state is RunState.FINISHED
    assert recording.names() == ["run_poses", "close_gripper", "run_poses"]  # not one blended call
    np.testing.assert_allclose(seen[0], a.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.HIGH and sim.gripper_opening() == 0.0


def test_a_pallet_takes_the_next_cell_each_pass_and_starts_over(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    pallet = PalletStep(
        name="tray",
        corners=("A", "B", "C"),
        rows=2,
        columns=3,
        approach_mm=40.0,
        speed=100.0,
        body=(GripperStep(action=GripperAction.CLOSE, timeout_ms=50),),
    )
    program = program_of(LoopStep(times=7, body=(pallet,)), extra=(a, b, c))
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    assert runner.run(program).state is RunState.FINISHED

    cells = pallet_cells((a.position, b.position, c.position), 2, 3, 1, 0.0)
    expected = [cells[k % 6] for k in range(7)]  # row by row, then the first cell again
    calls = [args for name, args in recording.calls if name == "run_positions"]
    assert len(calls) == 7 * 3  # above, down, up
    downs = [calls[3 * k + 1][0][0] for k in range(7)]
    assert downs == expected
    above = calls[0][0][0]
    assert above.point.z == pytest.approx(expected[0].point.z + 0.04)
    np.testing.assert_allclose(cells[2].point.x, b.position.point.x)  # the row ends at the second corner
    np.testing.assert_allclose(cells[3].point.y, c.position.point.y)  # the column ends at the third
    np.testing.assert_allclose(
        tcp(sim), [expected[-1].point.x, expected[-1].point.y, above.point.z], atol=POSITION_TOL_M
    )


def test_a_call_runs_the_other_program_and_recursion_is_refused_before_moving(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint], tmp_path: Path
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    store = ProgramStore(tmp_path)
    store.save(program_of(move(b), OutputStep(port=2, level=SignalLevel.HIGH)), "place")
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now, load=store.load)
    result = runner.run(program_of(move(a), CallStep(program="place")))
    assert result.state is RunState.FINISHED
    np.testing.assert_allclose(angles(sim), b.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(2) is SignalLevel.HIGH

    store.save(program_of(CallStep(program="ping")), "pong")
    store.save(program_of(move(a), CallStep(program="pong")), "ping")
    before = angles(sim)
    with pytest.raises(PlanError, match="calls itself: ping -> pong -> ping"):
        runner.run(store.load("ping"))
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)
    with pytest.raises(PlanError, match="Step 1 \\(Call nowhere\\): No program named 'nowhere'"):
        runner.run(program_of(CallStep(program="nowhere")))


def test_a_failed_run_resumes_at_the_failed_step_and_not_before(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b = waypoints["A"], waypoints["B"]
    program = program_of(
        move(a),
        OutputStep(port=1, level=SignalLevel.HIGH),
        LoopStep(times=1, body=(WaitInputStep(port=3, level=SignalLevel.HIGH, timeout_ms=200),)),
        move(b),
    )
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    failed = runner.run(program)
    assert failed.state is RunState.FAILED and failed.failed_step == 3  # line 4: inside the loop
    assert (
        failed.message == "Step 4 (Wait DI3 HIGH (timeout 200 ms)) failed: DI3 did not go HIGH within 200 ms"
    )
    assert runner.can_resume

    sim.set_input(3, SignalLevel.HIGH)  # the operator fixed the cause
    resumed = runner.resume()
    assert resumed.state is RunState.FINISHED
    # The failure froze the arm; nothing before the failed step ran again.
    assert recording.names() == ["run_poses", "set_output", "freeze", "run_poses"]
    np.testing.assert_allclose(angles(sim), b.pose.angles, atol=ANGLE_TOL_DEG)


def test_run_from_a_line_skips_what_is_before_it(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    program = program_of(
        move(a),
        OutputStep(port=1, level=SignalLevel.HIGH),
        LoopStep(times=2, body=(move(b).step, move(c).step)),
        extra=(b, c),
    )
    recording = Recording(sim)
    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now)
    result = runner.run(program, start_line=4)  # line 5: "Move to C" inside the loop
    assert result.state is RunState.FINISHED
    poses = [args[0] for name, args in recording.calls if name == "run_poses"]
    assert [[p.angles for p in call] for call in poses] == [[c.pose.angles], [b.pose.angles, c.pose.angles]]
    assert sim.get_output(1) is SignalLevel.LOW


def test_blended_moves_split_at_a_hundred_targets(waypoints: dict[str, Waypoint]) -> None:
    a, b = waypoints["A"], waypoints["B"]
    program = program_of(*[move(a if k % 2 else b) for k in range(250)])
    groups = compile_program(program)
    assert all(isinstance(node, MoveGroup) for node in groups)
    sizes = [len(node.targets) for node in groups if isinstance(node, MoveGroup)]
    assert sizes == [100, 100, 50]


def test_a_refused_pose_inside_a_loop_names_its_line(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    far = Waypoint(name="Far", pose=Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0]), position=a.position)
    program = program_of(CommentStep(text="start"), LoopStep(times=2, body=(move(far).step,)), extra=(far,))
    result = ProgramRunner(sim, sleep=clock.advance, now=clock.now).run(program)
    assert result.state is RunState.FAILED and result.failed_step == 2
    assert result.message == "Step 3 (Move J to Far @ 50%) failed: Unreachable Pose"


class FailingInput:
    """The simulator, whose input reads fail (a controller that stopped answering) after `after` reads."""

    def __init__(self, sim: SimController, after: int) -> None:
        self._sim, self.reads_left = sim, after

    def __getattr__(self, name: str) -> Any:  # the simulator's: a Controller to the type checker
        return getattr(self._sim, name)

    def get_input(self, port: int) -> SignalLevel:
        self.reads_left -= 1
        if self.reads_left < 0:
            raise NotResponding()
        return self._sim.get_input(port)


def test_a_failed_input_read_at_the_end_of_a_pass_fails_the_loop_and_a_retry_reads_again(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    loop = LoopStep(mode=LoopMode.UNTIL, port=1, level=SignalLevel.HIGH, body=(move(a).step,))
    flaky = FailingInput(sim, after=1)  # the check before the first pass answers, the next does not
    runner = ProgramRunner(flaky, sleep=clock.advance, now=clock.now)
    failed = runner.run(program_of(CommentStep(text="cell"), loop, extra=(a,)))
    assert failed.state is RunState.FAILED and failed.failed_step == 1
    assert failed.message.startswith("Step 2 (Loop until DI1 HIGH) failed: ")
    flaky.reads_left = 10
    sim.set_input(1, SignalLevel.HIGH)
    assert runner.resume().state is RunState.FINISHED
