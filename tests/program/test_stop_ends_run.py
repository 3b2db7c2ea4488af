"""A stop heard anywhere (the page's Freeze, another browser, `PUT /freeze`, a protective stop) ends a
running program whatever its step, moving or not, a blended group and the moment between two steps too:
"Stopped at step N by <cause>", nothing after it is sent, the arm stays where the stop left it, and Retry or
Skip go on from there as after a failure.

The stop is delivered as the API's stop middleware delivers it: told to the runner first, then the arm is
frozen. The runner's sleeps advance the simulator's fake clock, so each case runs in milliseconds."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import pytest

from pendant.controller import SignalLevel
from pendant.program import (
    CallStep,
    GripperAction,
    GripperStep,
    LoopStep,
    OutputStep,
    Program,
    ProgramRunner,
    RunState,
    Step,
    WaitInputStep,
    WaitStep,
    Waypoint,
)
from pendant.program.runner import RunProgress
from pendant.sim import FakeClock, SimController
from tests.support.programs import POLL_S, Taught, move, program_of, runner_doing_at_step

CAUSE = "Freeze from the API (127.0.0.1)"
ANGLE_TOL_DEG = 1e-6
HELD_S = 3.0  # how long the arm is watched after the stop: it must not go on to the next motion
IN_STEP_S = 0.2  # the stop comes this long into the step it interrupts (or at its start: 0)
SLOW_VIEW_S = 0.3  # a listener this slow still runs on the run's thread when the next start comes


def stop_during(
    runner: ProgramRunner, sim: SimController, clock: FakeClock, line: int, after_s: float
) -> Callable[[float], None]:
    """A sleep for the runner that, `after_s` into step `line` (0-based), delivers a stop as the API does."""
    entered: list[float] = []
    done = False

    def on_progress(progress: object) -> None:
        if getattr(progress, "step_index", None) == line and not entered:
            entered.append(clock.now())
            if after_s == 0.0:
                deliver()

    def deliver() -> None:
        nonlocal done
        if not done:
            done = True
            runner.stop_heard(CAUSE)
            sim.freeze()

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if entered and clock.now() - entered[0] >= after_s:
            deliver()

    runner.add_listener(on_progress)
    return sleep


def angles(sim: SimController) -> np.ndarray:
    return np.array(sim.get_pose().angles)


def runner_stopped_at(
    sim: SimController,
    clock: FakeClock,
    line: int,
    after_s: float,
    load: Callable[[str], Program] | None = None,
) -> ProgramRunner:
    hook: list[Callable[[float], None]] = []
    runner = ProgramRunner(sim, now=clock.now, sleep=lambda dt: hook[0](dt), poll_s=POLL_S, load=load)
    hook.append(stop_during(runner, sim, clock, line, after_s))
    return runner


class Case(NamedTuple):
    steps: list[Step | Taught]
    during: int  # the 0-based line the stop comes in
    after_s: float  # how far into it
    stopped_at: int  # the 0-based line the run says it stopped at (where Retry goes on)


def cases(waypoints: dict[str, Waypoint]) -> dict[str, Case]:
    a, b = waypoints["A"], waypoints["B"]
    gripper = GripperStep(action=GripperAction.CLOSE, timeout_ms=500)
    wait_input = WaitInputStep(port=1, level=SignalLevel.HIGH, timeout_ms=5000)
    loop = LoopStep(times=3, body=(WaitStep(ms=100),))
    return {
        "gripper": Case([move(a), gripper, move(b)], 1, IN_STEP_S, 1),
        "wait": Case([move(a), WaitStep(ms=2500), move(b)], 1, IN_STEP_S, 1),
        "wait for input": Case([move(a), wait_input, move(b)], 1, IN_STEP_S, 1),
        "output (as it starts)": Case(
            [move(a), OutputStep(port=1, level=SignalLevel.HIGH), move(b)], 1, 0.0, 1
        ),
        "inside a loop pass": Case([move(a), loop, move(b)], 2, 0.05, 2),
        # The first pass's wait just ended: the loop's check (line 2) is what comes next.
        "between loop passes": Case([move(a), loop, move(b)], 2, 0.1, 1),
        "a motion": Case([move(a), WaitStep(ms=100), move(b)], 2, IN_STEP_S, 2),
        "a blended group": Case(
            [move(a), WaitStep(ms=100), move(b, blend_mm=20.0), move(waypoints["C"])], 2, IN_STEP_S, 2
        ),
        # As step 3 begins, before it sends anything: the step just done (DO2) stays done.
        "between two steps": Case([move(a), OutputStep(port=2, level=SignalLevel.HIGH), move(b)], 2, 0.0, 2),
    }


CASE_NAMES = [
    "gripper",
    "wait",
    "wait for input",
    "output (as it starts)",
    "inside a loop pass",
    "between loop passes",
    "a motion",
    "a blended group",
    "between two steps",
]


@pytest.mark.parametrize("case", CASE_NAMES)
def test_a_stop_heard_ends_the_run_at_its_step_and_the_arm_stays(
    case: str, sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    steps, during, after_s, stopped_at = cases(waypoints)[case]
    program = program_of(*steps)
    runner = runner_stopped_at(sim, clock, during, after_s)

    result = runner.run(program)

    assert result.state is RunState.STOPPED, result.message
    assert result.message == f"Stopped at step {stopped_at + 1} by {CAUSE}"
    assert result.failed_step == stopped_at  # the banner's Retry / Skip act on it
    held = angles(sim)
    clock.advance(HELD_S)
    np.testing.assert_allclose(angles(sim), held, atol=ANGLE_TOL_DEG)  # nothing after the stop was sent
    assert not np.allclose(held, waypoints["B"].pose.angles, atol=0.5)
    assert sim.get_output(1) is SignalLevel.LOW
    assert runner.can_resume


def test_retry_after_a_stop_goes_on_from_the_stopped_step_to_the_end(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(move(waypoints["A"]), WaitStep(ms=2500), move(waypoints["B"]))
    runner = runner_stopped_at(sim, clock, 1, IN_STEP_S)
    assert runner.run(program).state is RunState.STOPPED

    assert runner.resume().state is RunState.FINISHED
    np.testing.assert_allclose(angles(sim), waypoints["B"].pose.angles, atol=ANGLE_TOL_DEG)


def test_skip_after_a_stop_leaves_out_the_stopped_step(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(
        move(waypoints["A"]),
        WaitStep(ms=2500),
        OutputStep(port=2, level=SignalLevel.HIGH),
        move(waypoints["B"]),
    )
    runner = runner_stopped_at(sim, clock, 1, IN_STEP_S)
    assert runner.run(program).state is RunState.STOPPED
    started = clock.now()

    assert runner.skip().state is RunState.FINISHED
    assert sim.get_output(2) is SignalLevel.HIGH
    assert clock.now() - started < 2.5  # the rest of the wait was not waited


def test_a_stop_inside_a_called_program_ends_the_caller_too(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    called = program_of(WaitStep(ms=2000), OutputStep(port=1, level=SignalLevel.HIGH), name="sub")
    program = program_of(move(waypoints["A"]), CallStep(program="sub"), move(waypoints["B"]))
    loads: dict[str, Program] = {"sub": called}
    runner = runner_stopped_at(sim, clock, 1, IN_STEP_S, load=loads.__getitem__)

    result = runner.run(program)

    assert result.state is RunState.STOPPED and result.message.endswith(f"by {CAUSE}")
    clock.advance(HELD_S)
    assert sim.get_output(1) is SignalLevel.LOW
    np.testing.assert_allclose(angles(sim), waypoints["A"].pose.angles, atol=ANGLE_TOL_DEG)


def test_a_paused_run_that_hears_a_stop_is_stopped_not_resumed_by_run(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    program = program_of(move(waypoints["A"]), WaitStep(ms=2500), move(waypoints["B"]))
    runner = runner_doing_at_step(sim, clock, 1, lambda runner: runner.pause())
    assert runner.run(program).state is RunState.PAUSED

    runner.stop_heard(CAUSE)

    assert runner.progress.state is RunState.STOPPED
    assert runner.progress.message == f"Stopped at step 2 by {CAUSE}"
    assert runner.can_resume  # Retry is the operator's, as after a failure


def test_a_stop_heard_before_a_run_does_not_end_the_next_run(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    runner = ProgramRunner(sim, now=clock.now, sleep=clock.advance, poll_s=POLL_S)
    runner.stop_heard(CAUSE)  # the arm was idle: nothing to end

    result = runner.run(program_of(move(waypoints["A"]), WaitStep(ms=200), move(waypoints["B"])))

    assert result.state is RunState.FINISHED


def test_the_programs_own_stop_ends_the_run_for_good(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    """The program's Stop (and the banner's Stop program) end the run: no Retry is left to press."""
    program = program_of(move(waypoints["A"]), WaitStep(ms=2500), move(waypoints["B"]))

    def press_stop(runner: ProgramRunner) -> None:
        runner.stop_heard("Stop by Tab 1")  # the page announces the Stop, then calls stop()
        runner.stop()

    runner = runner_doing_at_step(sim, clock, 1, press_stop)

    result = runner.run(program)

    assert result.state is RunState.STOPPED and result.message == "Stopped at step 2 by Stop by Tab 1"
    assert not runner.can_resume


def test_resume_pressed_as_the_stop_is_announced_goes_on_rather_than_being_refused(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    """The banner shows the stopped run while the run's thread is still telling its other listeners: a
    Retry pressed then starts the run again (it was refused "A program is already running")."""
    program = program_of(move(waypoints["A"]), WaitStep(ms=2500), move(waypoints["B"]))
    runner = runner_stopped_at(sim, clock, 1, IN_STEP_S)
    announced = threading.Event()

    def slow_view(progress: RunProgress) -> None:
        if progress.state is RunState.STOPPED:
            announced.set()
            time.sleep(SLOW_VIEW_S)  # another browser's view, slow to draw

    runner.add_listener(slow_view)
    runner.start(lambda: runner.run(program))
    assert announced.wait(HELD_S * 10)  # a safety net, as the join below: the thread may lack the CPU

    runner.start(runner.resume)

    assert runner.join(HELD_S * 10)
    assert runner.progress.state is RunState.FINISHED, runner.progress.message
