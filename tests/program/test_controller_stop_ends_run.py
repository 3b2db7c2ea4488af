"""A stop the controller reports itself ends a running program as a stop (issue 31): a protective stop from
a bound input, a fault (ERROR), an emergency, the arm relaxed by another client. No stop was announced to
the pendant, so the run learns of it only from the controller, while the arm stands still (a wait, a
gripper step), moves, or between two steps. The run ends "Stopped at step N by the controller (...)", with
Retry and Skip left as after any stop, and nothing is sent after it: on main a relaxed arm between two steps
was sent its next move (the run went on to "Finished"), and the others ended as a failed step."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np
import pytest

from pendant.controller import Controller, Pose, Position, SignalLevel
from pendant.kinematics import ArmModel
from pendant.planning.live import ControllerPlanner
from pendant.program import GripperAction, GripperStep, ProgramRunner, RunState, Step, WaitStep, Waypoint
from pendant.program.runner import RunProgress
from pendant.sim import FakeClock, SimController
from pendant.sim.states import Fault
from tests.support.programs import POLL_S, Recording, Taught, angles, move, program_of

BOUND_PORT = 3
HELD_S = 3.0
ANGLE_TOL_DEG = 1e-6
SLOW_PERCENT = 10.0
IN_STEP_S = 0.2  # how far into its step the stop comes (0: as the step begins, before it sends anything)


def input_goes_high(sim: SimController) -> None:
    """A sensor wired to the bound input trips: the controller's protective stop."""
    sim.set_input(BOUND_PORT, SignalLevel.HIGH)


STOPS: dict[str, tuple[Callable[[SimController], None], str]] = {
    "protective stop (bound input)": (
        input_goes_high,
        "the controller (ERROR: a protective stop or a fault)",
    ),
    "fault (ERROR)": (
        lambda sim: sim.inject_fault(Fault.ERROR),
        "the controller (ERROR: a protective stop or a fault)",
    ),
    "emergency": (lambda sim: sim.inject_fault(Fault.EMERGENCY), "the controller (EMERGENCY)"),
    "relaxed by another client": (lambda sim: sim.relax(), "the controller (the arm relaxed, ZERO_GRAVITY)"),
}


class Case(NamedTuple):
    steps: list[Step | Taught]
    line: int  # 0-based: the step the stop comes in, and the one the run says it stopped at
    after_s: float


def cases(waypoints: dict[str, Waypoint]) -> dict[str, Case]:
    a, b = waypoints["A"], waypoints["B"]
    gripper = GripperStep(action=GripperAction.CLOSE, timeout_ms=2000)
    return {
        "wait": Case([move(a), WaitStep(ms=2500), move(b)], 1, IN_STEP_S),
        "gripper": Case([move(a), gripper, move(b)], 1, IN_STEP_S),
        "a motion": Case([move(a), WaitStep(ms=100), move(b, speed=SLOW_PERCENT)], 2, IN_STEP_S),
        "between two steps": Case([move(a), WaitStep(ms=100), move(b, speed=SLOW_PERCENT)], 2, 0.0),
    }


def held_pose(sim: SimController) -> np.ndarray | None:
    """Where the arm is; None in an emergency, when the controller answers nothing."""
    try:
        return angles(sim)
    except Exception:
        return None


@pytest.mark.parametrize("step", ["wait", "gripper", "a motion", "between two steps"])
@pytest.mark.parametrize("stop", list(STOPS))
def test_a_stop_the_controller_reports_ends_the_run_as_a_stop_and_nothing_is_sent_after(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint], stop: str, step: str
) -> None:
    steps, line, after_s = cases(waypoints)[step]
    make_stop, cause = STOPS[stop]
    sim.bind_stop(BOUND_PORT, SignalLevel.HIGH)
    recording = Recording(sim)
    entered: list[float] = []
    sent_before: list[int] = []

    def deliver() -> None:
        if not sent_before:
            sent_before.append(len(recording.calls))
            make_stop(sim)

    def on_progress(progress: RunProgress) -> None:
        if progress.step_index == line and progress.state is RunState.RUNNING and not entered:
            entered.append(clock.now())
            if after_s == 0.0:
                deliver()

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if entered and clock.now() - entered[0] >= after_s:
            deliver()

    runner = ProgramRunner(recording, now=clock.now, sleep=sleep, poll_s=POLL_S)
    runner.add_listener(on_progress)

    result = runner.run(program_of(*steps))

    assert result.state is RunState.STOPPED, result.message
    assert result.message == f"Stopped at step {line + 1} by {cause}"
    assert result.failed_step == line and runner.can_resume  # the banner's Retry / Skip
    sent_after = [name for name, _ in recording.calls[sent_before[0] :] if name != "freeze"]
    assert sent_after == [], f"sent after the controller stopped: {sent_after}"
    held = held_pose(sim)
    clock.advance(HELD_S)
    if held is not None:
        np.testing.assert_allclose(angles(sim), held, atol=ANGLE_TOL_DEG)
        assert not np.allclose(held, waypoints["B"].pose.angles, atol=0.5)


def test_an_arm_relaxed_while_a_planned_move_searches_is_not_sent_the_path(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    """The search takes its time before the path goes out: an arm another client relaxed meanwhile ends the
    run there (main, and this branch before: the path was the run's first command, sent unchecked)."""
    plans = ControllerPlanner(ArmModel.load("pulse75"))
    recording = Recording(sim)
    sent_before: list[int] = []

    def planner(controller: Controller, goal: Pose | Position, cancelled: Callable[[], bool]) -> list[Pose]:
        path = plans(controller, goal, cancelled)
        sent_before.append(len(recording.calls))
        sim.relax()  # while the path was being searched
        return path

    runner = ProgramRunner(recording, sleep=clock.advance, now=clock.now, poll_s=POLL_S, planner=planner)

    result = runner.run(program_of(move(waypoints["A"], planned=True), WaitStep(ms=100)))

    assert result.state is RunState.STOPPED, result.message
    assert result.message == f"Stopped at step 1 by {STOPS['relaxed by another client'][1]}"
    assert [name for name, _ in recording.calls[sent_before[0] :]] == []
    before = angles(sim)
    clock.advance(HELD_S)
    np.testing.assert_allclose(angles(sim), before, atol=ANGLE_TOL_DEG)
