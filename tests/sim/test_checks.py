"""Commands the controller refuses: out of reach, outside the limits, colliding, or out-of-range parameters.
A refused command changes nothing."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np
import pytest

from pendant.controller.errors import (
    MSG_COLLISION,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    BadRequest,
    Collision,
    ControllerError,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import MotionParams, MotionType, Pose, SignalLevel
from pendant.sim import FakeClock, SimController
from tests.support.sim_sampling import finish, position, shifted

JOINT_50 = MotionParams(speed=50)
LINEAR_50 = MotionParams(speed=50, motion_type=MotionType.LINEAR)
MOVING_TARGET = Pose(angles=[40.0, -70.0, 60.0, -100.0, -60.0, 30.0])
# Endpoints clear of everything, but turning joint 4 half a turn swings the wrist through the floor.
LOW_REACH = Pose(angles=[0.0, -10.0, -20.0, -90.0, -90.0, 0.0])
LOW_REACH_WRIST_TURNED = Pose(angles=[0.0, -10.0, -20.0, 90.0, -90.0, 0.0])


def _snapshot(sim: SimController) -> tuple[object, ...]:
    return sim.get_pose(), sim.get_motion_status(), len(sim.motions.queue), sim.gripper_opening()


def _assert_refused(
    sim: SimController,
    command: Callable[[], object],
    error: type[ControllerError],
    message: str | None = None,
) -> None:
    before = _snapshot(sim)
    with pytest.raises(error) as info:
        command()
    if message is not None:
        assert info.value.message == message
    assert _snapshot(sim) == before


def test_a_position_out_of_reach_is_unreachable(sim: SimController) -> None:
    far = position(3.0, 0.0, 0.5)
    _assert_refused(sim, lambda: sim.set_position(far, JOINT_50), Unreachable, MSG_UNREACHABLE_POSITION)
    _assert_refused(sim, lambda: sim.run_positions([far], LINEAR_50), Unreachable, MSG_UNREACHABLE_POSITION)


def test_a_pose_outside_the_joint_limits_is_unreachable(sim: SimController) -> None:
    beyond = Pose(angles=[0.0, -90.0, 90.0, -90.0, -90.0, 400.0])
    _assert_refused(sim, lambda: sim.set_pose(beyond, JOINT_50), Unreachable, MSG_UNREACHABLE_POSE)
    _assert_refused(
        sim, lambda: sim.run_poses([MOVING_TARGET, beyond], JOINT_50), Unreachable, MSG_UNREACHABLE_POSE
    )


def test_a_pose_in_the_floor_is_a_collision(sim: SimController) -> None:
    into_floor = Pose(angles=[0.0, 30.0, 0.0, -90.0, -90.0, 0.0])
    _assert_refused(sim, lambda: sim.set_pose(into_floor, JOINT_50), Collision, MSG_COLLISION)


def test_a_self_collision_is_refused(sim: SimController) -> None:
    folded_too_far = Pose(angles=[0.0, -90.0, 170.0, -90.0, -90.0, 0.0])
    _assert_refused(sim, lambda: sim.set_pose(folded_too_far, JOINT_50), Collision, MSG_COLLISION)


def test_a_path_through_the_floor_is_refused_though_both_ends_are_clear(
    sim: SimController, clock: FakeClock
) -> None:
    sim.set_pose(LOW_REACH, JOINT_50)
    finish(sim, clock)
    assert not sim.arm.in_collision(np.radians(LOW_REACH_WRIST_TURNED.angles))
    _assert_refused(sim, lambda: sim.set_pose(LOW_REACH_WRIST_TURNED, JOINT_50), Collision, MSG_COLLISION)


def test_a_linear_move_into_the_floor_is_refused(sim: SimController) -> None:
    here = sim.get_position()
    _assert_refused(sim, lambda: sim.set_position(shifted(here, dz=-0.6), LINEAR_50), Collision)


def test_a_linear_move_to_a_pose_on_another_ik_branch_is_unreachable(sim: SimController) -> None:
    # The same TCP pose with the wrist flipped: no straight line gets there without changing branch.
    q = np.radians(sim.get_pose().angles)
    T = sim.arm.fk(q)
    other = next(b for b in sim.arm.ik_all(T) if np.max(np.abs(b - q)) > 0.1)
    target = Pose(angles=np.degrees(other).tolist())
    _assert_refused(sim, lambda: sim.set_pose(target, LINEAR_50), Unreachable, MSG_UNREACHABLE_POSE)


def test_a_refused_command_leaves_the_queue_as_it_was(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(MOVING_TARGET, JOINT_50)
    clock.advance(0.2)
    _assert_refused(sim, lambda: sim.set_position(position(3.0, 0.0, 0.5), JOINT_50), Unreachable)
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, MOVING_TARGET.angles)


@pytest.mark.parametrize(
    "params",
    [
        MotionParams(speed=0.0),
        MotionParams(speed=100.5),
        MotionParams(speed=float("nan")),
        MotionParams(speed=50, tcp_max_velocity=0.0),
        MotionParams(speed=50, acceleration=200.5),
        MotionParams(speed=50, tcp_max_velocity=2.5),
        MotionParams(speed=50, acceleration=0.0),
    ],
)
def test_out_of_range_motion_parameters_are_refused(sim: SimController, params: MotionParams) -> None:
    _assert_refused(sim, lambda: sim.set_pose(MOVING_TARGET, params), PreconditionFailed)
    _assert_refused(sim, lambda: sim.set_position(sim.get_position(), params), PreconditionFailed)
    with pytest.raises(PreconditionFailed) as info:
        sim.run_poses([MOVING_TARGET], params)
    assert "between" in info.value.message  # says what the range is


def test_empty_waypoint_lists_are_bad_requests(sim: SimController) -> None:
    _assert_refused(sim, lambda: sim.run_poses([], JOINT_50), BadRequest)
    _assert_refused(sim, lambda: sim.run_positions([], JOINT_50), BadRequest)


def test_ports_and_gripper_timeouts_out_of_range_are_refused(sim: SimController) -> None:
    for port in (0, 3):
        _assert_refused(sim, partial(sim.set_output, port, SignalLevel.HIGH), PreconditionFailed)
        _assert_refused(sim, partial(sim.get_output, port), PreconditionFailed)
    for port in (0, 5):
        _assert_refused(sim, partial(sim.get_input, port), PreconditionFailed)
        _assert_refused(sim, partial(sim.set_input, port, SignalLevel.HIGH), PreconditionFailed)
    _assert_refused(sim, lambda: sim.open_gripper(-1), PreconditionFailed)
