"""Finding 3 of the audit, second half: when a program fails on a controller error in the middle of a blended
group, the runner freezes the arm, so it does not finish the group while the page says "failed"."""

from __future__ import annotations

from typing import Any

import numpy as np

from pendant.controller import MotionStatus, MotionType, NotResponding
from pendant.program import ProgramRunner, RunState, Waypoint
from pendant.sim import FakeClock, SimController
from tests.support.programs import move, program_of

FAIL_AT_S = 0.5
SLOW_PERCENT = 10.0
ANGLE_TOL_DEG = 1e-3


class FlakyStatus:
    """The simulator, whose motion-status read fails once (a transient "Robot does not respond") after
    `fail_at` seconds: what a real controller under load may answer mid-run."""

    def __init__(self, sim: SimController, clock: FakeClock, fail_at: float) -> None:
        self._sim, self._clock, self._fail_at = sim, clock, fail_at
        self.failed = False

    def __getattr__(self, name: str) -> Any:  # the simulator's: a Controller to the type checker
        return getattr(self._sim, name)

    def get_motion_status(self) -> MotionStatus:
        if not self.failed and self._clock.now() >= self._fail_at:
            self.failed = True
            raise NotResponding()
        return self._sim.get_motion_status()


def test_a_controller_error_mid_group_freezes_the_arm_where_it_is(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    program = program_of(*(move(w, MotionType.JOINT, SLOW_PERCENT) for w in (a, b, c)))
    flaky = FlakyStatus(sim, clock, clock.now() + FAIL_AT_S)
    runner = ProgramRunner(flaky, sleep=clock.advance, now=clock.now, poll_s=0.05)

    result = runner.run(program)

    assert flaky.failed
    assert result.state is RunState.FAILED
    assert "Robot does not respond" in result.message
    where_it_failed = np.asarray(sim.get_pose().angles)
    clock.advance(60.0)  # long enough to finish the whole group, had it gone on
    assert sim.get_motion_status() is MotionStatus.IDLE
    np.testing.assert_allclose(sim.get_pose().angles, where_it_failed, atol=ANGLE_TOL_DEG)
    assert not np.allclose(sim.get_pose().angles, c.pose.angles, atol=1.0), "the arm finished the group"
