"""A stop sent to a program the page runs, inside one of its steps, and what the user then sees: the run
ends naming the stop, the arm stays where the stop left it and the step after it (DO2 HIGH) never runs.
Shared by the tests of the page's stop sources (tests/ui/test_page_stops_end_run.py) and of the API's stops
with viser's callback pool held (tests/ui/test_stops_beside_the_pool.py)."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from pendant.controller import MotionStatus, Pose, SignalLevel
from pendant.program import (
    GripperAction,
    GripperStep,
    OutputStep,
    RunState,
    Step,
    WaitInputStep,
    WaitStep,
    Waypoint,
)
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from tests.support.doubles import OPERATOR
from tests.support.programs import Taught, move, program_of
from tests.support.waiting import wait_until

FAR_DEG = [120.0, -90.0, 90.0, -90.0, -90.0, 0.0]
SLOW_PERCENT = 5.0
LONG_MS = 20_000  # a still step lasts far longer than the test: only the stop ends it
INTO_STEP_S = 0.3
STILL_TOL_DEG = 0.01
AFTER_PORT = 2  # the step after the stopped one sets it HIGH


def run_steps(far: Waypoint) -> dict[str, Step | Taught]:
    """The steps a stop is sent in: three still ones and a motion towards `far`."""
    return {
        "wait": WaitStep(ms=LONG_MS),
        "wait for an input": WaitInputStep(port=1, level=SignalLevel.HIGH, timeout_ms=LONG_MS),
        "gripper": GripperStep(action=GripperAction.CLOSE, timeout_ms=LONG_MS),
        "motion": move(far, speed=SLOW_PERCENT),
    }


def stop_the_run(
    page: PendantUI,
    sim: SimController,
    step: str,
    send: Callable[[], object],
    cause: str,
    *,
    held_s: float,
    timeout_s: float,
    ended: Callable[[], object] = lambda: None,
) -> str:
    """Run `step` then DO2 HIGH, `send` the stop 0.3 s into the step: the run ends "Stopped at step 1 by
    `cause`..." (then `ended` is called), the arm stays put for `held_s` and DO2 is never set. Returns the
    run's message."""
    programs = page.programs
    sim.reset()
    far = Waypoint(name="Far", pose=Pose(angles=FAR_DEG), position=sim.get_position())
    programs.open_uploaded(
        program_of(run_steps(far)[step], OutputStep(port=AFTER_PORT, level=SignalLevel.HIGH))
    )
    programs.start_run(supervisor=OPERATOR)
    wait_until(lambda: programs.progress.state is RunState.RUNNING, timeout_s, "the run")
    if step == "motion":
        wait_until(lambda: sim.get_motion_status() is MotionStatus.RUNNING, timeout_s, "the motion")
    time.sleep(INTO_STEP_S)

    send()

    wait_until(lambda: programs.progress.state is RunState.STOPPED, timeout_s, "the run stopped")
    assert programs.runner.join(timeout_s)
    ended()
    message = programs.progress.message
    assert message.startswith(f"Stopped at step 1 by {cause}"), message
    held = np.array(sim.get_pose().angles)
    time.sleep(held_s)
    np.testing.assert_allclose(sim.get_pose().angles, held, atol=STILL_TOL_DEG)
    assert sim.get_output(AFTER_PORT) is SignalLevel.LOW  # the step after the stop never ran
    return message
