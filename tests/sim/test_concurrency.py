"""Planning happens outside the simulator's lock: freeze and reads never wait for a plan, a plan made from a
queue end that moved meanwhile is made again, and the queue and the runs are capped."""

from __future__ import annotations

import itertools
import threading
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

from pendant.controller.errors import Collision, NotResponding, PreconditionFailed
from pendant.controller.types import MotionParams, MotionStatus, MotionType, Pose
from pendant.kinematics.limits import JOINT_MAX_SPEED_RAD_S
from pendant.sim import FakeClock, SimController
from pendant.sim.controller import MAX_QUEUED_COMMANDS, MAX_WAYPOINTS, MSG_QUEUE_BUSY
from tests.support.sim_sampling import ANGLE_TOL_DEG, POS_TOL_M, finish, record, shifted
from tests.support.waiting import SAFETY_NET_S

# Not a timing threshold: long enough on any machine; only a thread stuck behind a lock runs into it.
HANG_S = SAFETY_NET_S
SPEED_TOL = 1e-6
JOINT_50 = MotionParams(speed=50)
LINEAR_50 = MotionParams(speed=50, motion_type=MotionType.LINEAR)
X = Pose(angles=[30.0, -80.0, 80.0, -90.0, -90.0, 0.0])
Y = Pose(angles=[-30.0, -80.0, 80.0, -90.0, -90.0, 0.0])


class HeldPlanner:
    """Makes the first call of one planner method wait for `release` (a plan that takes long)."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch, sim: SimController, method: str) -> None:
        self.started = threading.Event()
        self.release = threading.Event()
        self.calls = 0
        self.first_raises: Exception | None = None
        original = getattr(sim.planner, method)
        count = itertools.count()

        def held(*args: Any, **kwargs: Any) -> Any:
            self.calls += 1
            if next(count) == 0:
                self.started.set()
                assert self.release.wait(HANG_S)
                if self.first_raises is not None:
                    raise self.first_raises
            return original(*args, **kwargs)

        monkeypatch.setattr(sim.planner, method, held)


def in_thread(call: Callable[..., Any], *args: Any) -> tuple[threading.Thread, list[Any]]:
    """Start `call(*args)` in a thread; the list gets its result or its exception."""
    outcome: list[Any] = []

    def run() -> None:
        try:
            outcome.append(call(*args))
        except Exception as error:  # handed to the test
            outcome.append(error)

    thread = threading.Thread(target=run, daemon=True)
    thread.start()
    return thread, outcome


def finished(call: Callable[..., Any], *args: Any) -> list[Any]:
    """Run `call` in a thread and check it did not wait for anything (the held plan)."""
    thread, outcome = in_thread(call, *args)
    thread.join(HANG_S)
    assert not thread.is_alive(), f"{call.__name__} waited for the plan"
    return outcome


def assert_smooth_to(sim: SimController, clock: FakeClock, target: Pose, speed: float) -> None:
    """The arm moves to `target` without a jump: no joint ever faster than speed % of its limit."""
    rec = record(sim, clock)
    limit = np.degrees(JOINT_MAX_SPEED_RAD_S) * speed / 100.0
    assert np.all(np.abs(rec.joint_speed_deg_s) <= limit * (1 + SPEED_TOL))
    assert np.allclose(sim.get_pose().angles, target.angles, atol=ANGLE_TOL_DEG)


def test_freeze_and_reads_do_not_wait_for_a_plan(
    sim: SimController, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    held = HeldPlanner(monkeypatch, sim, "linear")
    target = shifted(sim.get_position(), dz=-0.05)
    mover, outcome = in_thread(sim.run_positions, [target], LINEAR_50)
    try:
        assert held.started.wait(HANG_S)
        for call in (sim.freeze, sim.get_pose, sim.get_position, sim.get_motion_status, sim.get_motors):
            assert not isinstance(finished(call)[0], Exception)
    finally:
        held.release.set()
        mover.join(HANG_S)
    # Freeze wins: the command was accepted, but the freeze cancelled it while it was planned.
    assert outcome == [None]
    before = sim.get_position().point.z
    finish(sim, clock)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert abs(sim.get_position().point.z - before) < POS_TOL_M


def test_a_command_queued_while_planning_makes_the_plan_start_from_its_end(
    sim: SimController, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    held = HeldPlanner(monkeypatch, sim, "joint")
    mover, outcome = in_thread(sim.set_pose, X, JOINT_50)
    try:
        assert held.started.wait(HANG_S)
        assert finished(sim.set_pose, Y, JOINT_50) == [None]
    finally:
        held.release.set()
        mover.join(HANG_S)
    assert outcome == [None]
    assert held.calls == 3  # X planned from home, Y, X again from Y
    assert_smooth_to(sim, clock, X, JOINT_50.speed)


def test_a_freeze_while_planning_cancels_the_plan_and_the_arm_stays_where_it_stopped(
    sim: SimController, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    sim.set_pose(Y, JOINT_50)
    clock.advance(0.3)
    held = HeldPlanner(monkeypatch, sim, "joint")
    mover, outcome = in_thread(sim.set_pose, X, JOINT_50)
    try:
        assert held.started.wait(HANG_S)
        finished(sim.freeze)
        stopped = sim.get_pose().angles
    finally:
        held.release.set()
        mover.join(HANG_S)
    assert outcome == [None]
    assert sim.get_pose().angles == pytest.approx(stopped, abs=ANGLE_TOL_DEG)
    clock.advance(5.0)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == pytest.approx(stopped, abs=ANGLE_TOL_DEG)


def test_a_fault_while_planning_wins_and_nothing_is_queued(
    sim: SimController, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    from pendant.sim import Fault

    home = sim.get_pose().angles
    held = HeldPlanner(monkeypatch, sim, "joint")
    mover, outcome = in_thread(sim.set_pose, X, JOINT_50)
    try:
        assert held.started.wait(HANG_S)
        finished(sim.inject_fault, Fault.ERROR)
    finally:
        held.release.set()
        mover.join(HANG_S)
    assert isinstance(outcome[0], NotResponding)
    clock.advance(5.0)
    assert sim.get_motion_status() is MotionStatus.ERROR
    assert sim.get_pose().angles == home


def test_a_refusal_planned_from_a_stale_queue_end_is_planned_again(
    sim: SimController, clock: FakeClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    held = HeldPlanner(monkeypatch, sim, "joint")
    held.first_raises = Collision()  # as if the way from the old queue end were blocked
    mover, outcome = in_thread(sim.set_pose, X, JOINT_50)
    try:
        assert held.started.wait(HANG_S)
        sim.set_pose(Y, JOINT_50)
    finally:
        held.release.set()
        mover.join(HANG_S)
    assert outcome == [None]
    assert_smooth_to(sim, clock, X, JOINT_50.speed)


def test_a_queue_end_that_keeps_moving_gives_up_after_a_few_plans(
    sim: SimController, monkeypatch: pytest.MonkeyPatch
) -> None:
    original = sim.planner.joint

    def planner_with_a_busy_neighbour(*args: Any, **kwargs: Any) -> Any:
        sim.set_tool(sim.get_tool())  # another client sets the tool during every plan
        return original(*args, **kwargs)

    monkeypatch.setattr(sim.planner, "joint", planner_with_a_busy_neighbour)
    with pytest.raises(PreconditionFailed) as refused:
        sim.set_pose(X, JOINT_50)
    assert refused.value.message == MSG_QUEUE_BUSY
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_a_run_takes_at_most_max_waypoints(sim: SimController, clock: FakeClock) -> None:
    home = sim.get_pose()
    too_many = [X, Y] * (MAX_WAYPOINTS // 2) + [X]
    with pytest.raises(PreconditionFailed) as refused:
        sim.run_poses(too_many, JOINT_50)
    assert (
        refused.value.message == f"waypoints must be 1 to {MAX_WAYPOINTS} per run (got {MAX_WAYPOINTS + 1})"
    )
    assert sim.get_motion_status() is MotionStatus.IDLE
    with pytest.raises(PreconditionFailed):
        sim.run_positions([sim.get_position()] * (MAX_WAYPOINTS + 1), JOINT_50)
    assert sim.get_motion_status() is MotionStatus.IDLE
    sim.run_poses([home] * MAX_WAYPOINTS, JOINT_50)  # the limit itself is accepted


def test_the_queue_holds_at_most_max_queued_commands(sim: SimController, clock: FakeClock) -> None:
    for _ in range(MAX_QUEUED_COMMANDS):
        sim.close_gripper(1000)
    busy_until = sim.busy_until()
    refusals = (
        lambda: sim.open_gripper(1000),
        lambda: sim.set_pose(X, JOINT_50),
        lambda: sim.set_position(sim.get_position(), JOINT_50),
        sim.pack,
    )
    for refused_call in refusals:
        with pytest.raises(PreconditionFailed) as refused:
            refused_call()
        assert refused.value.message.startswith(f"queue must hold at most {MAX_QUEUED_COMMANDS} commands")
    assert sim.busy_until() == busy_until
    clock.advance(1.0)  # one done: room for one more
    sim.set_pose(X, JOINT_50)
