"""Programs run on any controller: the runner over RemoteController (talking to the simulator's REST API
through Starlette's TestClient, no network) does what it does on the simulator in-process."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller import Controller, MotionType, Pose, SignalLevel
from pendant.controller.types import OUTPUT_PORTS
from pendant.program import (
    OutputStep,
    Program,
    ProgramRunner,
    RunState,
    WaitStep,
    Waypoint,
)
from pendant.remote import RemoteController
from pendant.sim import FakeClock, SimController
from tests.support.programs import POLL_S, angles, move, program_of, sleeping

ANGLE_TOL_DEG = 1e-6
POS_TOL_M = 1e-6
WAIT_MS = 300


def pick_and_place(waypoints: dict[str, Waypoint]) -> Program:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    return program_of(
        move(a),
        move(b),  # blended: one /poses/run
        OutputStep(port=1, level=SignalLevel.HIGH),
        WaitStep(ms=WAIT_MS),
        move(c, MotionType.LINEAR),
        move(a, MotionType.LINEAR),  # blended: one /positions/run
        OutputStep(port=2, level=SignalLevel.HIGH),
        OutputStep(port=1, level=SignalLevel.LOW),
    )


def outputs(controller: Controller) -> list[SignalLevel]:
    return [controller.get_output(port) for port in OUTPUT_PORTS]


def test_a_program_over_the_remote_controller_ends_where_it_ends_on_the_simulator(
    sim: SimController, clock: FakeClock, remote: RemoteController, waypoints: dict[str, Waypoint]
) -> None:
    program = pick_and_place(waypoints)
    direct_clock = FakeClock()
    direct = SimController("pulse75", direct_clock)
    on_sim = ProgramRunner(direct, sleep=direct_clock.advance, now=direct_clock.now, poll_s=POLL_S)
    over_http = ProgramRunner(remote, sleep=clock.advance, now=clock.now, poll_s=POLL_S)
    started = clock.now()

    expected = on_sim.run(program)
    result = over_http.run(program)

    assert expected.state is RunState.FINISHED
    assert result.state is RunState.FINISHED and result.progress == 1.0
    assert remote.get_pose().angles == pytest.approx(direct.get_pose().angles, abs=ANGLE_TOL_DEG)
    np.testing.assert_allclose(angles(sim), waypoints["A"].pose.angles, atol=ANGLE_TOL_DEG)
    here, there = remote.get_position().point, direct.get_position().point
    assert [here.x, here.y, here.z] == pytest.approx([there.x, there.y, there.z], abs=POS_TOL_M)
    assert outputs(remote) == outputs(direct) == [SignalLevel.LOW, SignalLevel.HIGH]
    # The wait and the motions took as long on the fake clock: nothing was skipped or run twice.
    assert clock.now() - started == pytest.approx(direct_clock.now(), abs=POLL_S)


def test_pause_holds_the_arm_and_resume_finishes_on_either_controller(
    controller: Controller, sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    holder: list[ProgramRunner] = []
    runner = ProgramRunner(controller, now=clock.now, sleep=sleeping(clock, 0.6, lambda: holder[0].pause()))
    holder.append(runner)

    paused = runner.run(program_of(move(a), move(b), move(c)))

    assert paused.state is RunState.PAUSED
    held = angles(sim)
    clock.advance(5.0)
    np.testing.assert_allclose(angles(sim), held, atol=ANGLE_TOL_DEG)  # frozen, not drifting on
    assert not np.allclose(held, c.pose.angles)
    assert runner.resume().state is RunState.FINISHED
    np.testing.assert_allclose(angles(sim), c.pose.angles, atol=ANGLE_TOL_DEG)


def test_stop_freezes_the_arm_and_nothing_after_it_runs_on_either_controller(
    controller: Controller, sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(
        move(waypoints["A"]), move(waypoints["B"]), OutputStep(port=1, level=SignalLevel.HIGH)
    )
    holder: list[ProgramRunner] = []
    runner = ProgramRunner(controller, now=clock.now, sleep=sleeping(clock, 0.4, lambda: holder[0].stop()))
    holder.append(runner)

    result = runner.run(program)

    assert result.state is RunState.STOPPED
    stopped = angles(sim)
    clock.advance(5.0)
    np.testing.assert_allclose(angles(sim), stopped, atol=ANGLE_TOL_DEG)
    assert sim.get_motion_status().value == "IDLE"
    assert sim.get_output(1) is SignalLevel.LOW
    assert runner.resume().state is RunState.STOPPED


def test_stop_during_a_wait_ends_the_run_before_the_next_step_on_either_controller(
    controller: Controller, sim: SimController, clock: FakeClock
) -> None:
    program = program_of(WaitStep(ms=2000), OutputStep(port=2, level=SignalLevel.HIGH))
    holder: list[ProgramRunner] = []
    runner = ProgramRunner(controller, now=clock.now, sleep=sleeping(clock, 0.5, lambda: holder[0].stop()))
    holder.append(runner)

    result = runner.run(program)

    assert result.state is RunState.STOPPED and result.message == "Stopped at step 1"
    assert sim.get_output(2) is SignalLevel.LOW


def test_a_refused_step_names_the_step_and_the_controllers_message_on_either_controller(
    controller: Controller, sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"]
    far = Waypoint(name="Far", pose=Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0]), position=a.position)
    runner = ProgramRunner(controller, sleep=clock.advance, now=clock.now)

    result = runner.run(program_of(move(a), OutputStep(port=1, level=SignalLevel.HIGH), move(far)))

    assert result.state is RunState.FAILED and result.failed_step == 2
    assert result.message == "Step 3 (Move J to Far @ 50%) failed: Unreachable Pose"
    assert sim.get_output(1) is SignalLevel.HIGH
