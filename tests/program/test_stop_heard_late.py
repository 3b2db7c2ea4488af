"""A stop the run hears late still ends it with the arm held (issue 31).

`pendant run --robot` hears its pendant's stops by polling GET /pendant/stops (every 50 ms): a stop that
reaches the pendant as one step ends (the arm at a waypoint, the next move about to go out) is heard only
after that move was sent. The pendant froze the arm when the stop came, then the move started it again.
The run must not say "Stopped" while the arm drives on to the next waypoint, and the poll made before
each command keeps that command from going out at all.

The pendant is played by the simulator (frozen when the stop arrives) and a list of stops it has heard
that the runner's poll (`hear_stops_now`) collects, or the watcher's thread one poll later."""

from __future__ import annotations

import numpy as np

from pendant.program import Program, ProgramRunner, RunState, WaitStep, Waypoint
from pendant.program.runner import RunProgress
from pendant.sim import FakeClock, SimController
from tests.support.programs import POLL_S, Recording, angles, move, program_of

CAUSE = "Freeze from the API (127.0.0.1)"
WATCH_POLL_S = 0.05  # stop_watch.POLL_S: the watcher's thread reads the count this often
HELD_S = 3.0
ANGLE_TOL_DEG = 1e-6
SLOW_PERCENT = 10.0  # the move to B lasts seconds: long enough to see it run on


class PendantStops:
    """The stops a pendant has heard and `pendant run` has not read yet."""

    def __init__(self) -> None:
        self.unread: list[str] = []
        self.runner: ProgramRunner | None = None

    def poll(self) -> None:
        """What StopWatch.poll_now does: every stop not read yet goes to the run."""
        assert self.runner is not None
        while self.unread:
            self.runner.stop_heard(self.unread.pop(0))


def runner_with_a_stop_at_step(
    sim: SimController, clock: FakeClock, line: int, *, poll_before_send: bool
) -> tuple[ProgramRunner, Recording, list[int]]:
    """A runner whose pendant hears a stop (and freezes the arm) the moment step `line` (0-based) begins;
    the watcher's thread passes it on one poll later. Returns the runner, its recorded commands and the
    number of commands sent when the stop arrived (filled in then)."""
    recording = Recording(sim)
    stops = PendantStops()
    arrived: list[float] = []
    sent_before: list[int] = []

    def on_progress(progress: RunProgress) -> None:
        if progress.step_index == line and progress.state is RunState.RUNNING and not arrived:
            arrived.append(clock.now())
            sim.freeze()  # the pendant stops the arm as the stop arrives
            stops.unread.append(CAUSE)
            sent_before.append(len(recording.calls))

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if arrived and clock.now() - arrived[0] >= WATCH_POLL_S:
            stops.poll()  # the watcher's thread

    runner = ProgramRunner(recording, now=clock.now, sleep=sleep, poll_s=POLL_S)
    stops.runner = runner
    runner.add_listener(on_progress)
    if poll_before_send:
        runner.hear_stops_now = stops.poll
    return runner, recording, sent_before


def a_wait_then_b(waypoints: dict[str, Waypoint]) -> Program:
    """Move J to A, wait 100 ms, a slow Move J to B (step 3: the stop comes as it begins)."""
    return program_of(move(waypoints["A"]), WaitStep(ms=100), move(waypoints["B"], speed=SLOW_PERCENT))


def test_a_stop_heard_after_the_next_move_went_out_ends_the_run_with_the_arm_held(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    """No poll before the send (as a stop still on its way to the pendant): the move goes out, the stop
    is heard 50 ms later, and the run freezes the arm it had just started (main: it ran on to B)."""
    runner, _, _ = runner_with_a_stop_at_step(sim, clock, 2, poll_before_send=False)
    result = runner.run(a_wait_then_b(waypoints))

    assert result.state is RunState.STOPPED and result.message == f"Stopped at step 3 by {CAUSE}"
    held = angles(sim)
    clock.advance(HELD_S)
    np.testing.assert_allclose(angles(sim), held, atol=ANGLE_TOL_DEG)  # not on its way to B
    assert not np.allclose(held, waypoints["B"].pose.angles, atol=0.5)


def test_a_stop_the_pendant_heard_before_the_next_move_keeps_that_move_from_going_out(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    """`pendant run` reads its pendant's stops before every command: nothing is sent after the stop."""
    runner, recording, sent_before = runner_with_a_stop_at_step(sim, clock, 2, poll_before_send=True)
    result = runner.run(a_wait_then_b(waypoints))

    assert result.state is RunState.STOPPED and result.message == f"Stopped at step 3 by {CAUSE}"
    sent_after = [name for name, _ in recording.calls[sent_before[0] :] if name != "freeze"]
    assert sent_after == [], f"sent after the stop: {sent_after}"
    np.testing.assert_allclose(angles(sim), waypoints["A"].pose.angles, atol=ANGLE_TOL_DEG)
