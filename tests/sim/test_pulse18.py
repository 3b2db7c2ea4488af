"""SDK 1.8.4's operations on the simulator, on a fake clock: cell, blends, actions, stops, jogging, states."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.cell_types import BoxObstacle, SimplifiedCapsuleObstacle, ToolShape
from pendant.controller.errors import Collision, PreconditionFailed
from pendant.controller.system_types import (
    FailureType,
    GripperAction,
    JoggingVector,
    JointMotionParameters,
    LinearMotionParameters,
    OutputAction,
    PositionWaypoint,
    RobotAction,
    SystemState,
)
from pendant.controller.types import (
    InterpolationType,
    MotionParams,
    Point,
    Position,
    RecoverResult,
    SignalLevel,
)
from pendant.sim import FakeClock, Fault, SimController
from tests.support.sim_sampling import finish, position, record, shifted

LINEAR = LinearMotionParameters(velocity=0.2, acceleration=1.0)
DEFAULT_BLEND_TOL_M = 1e-3
SAMPLING_SLACK = 1.01  # the closest sample may miss the closest point by a hair


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def sim(clock: FakeClock) -> SimController:
    return SimController(clock=clock)


def waypoint(p: Position, blend: float = 0.0, actions: list[RobotAction] | None = None) -> PositionWaypoint:
    return PositionWaypoint(point=p.point, rotation=p.rotation, blend=blend, actions=actions)


def box_at(p: Position, name: str = "box", side: float = 0.04) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=side, y=side, z=side),
        centerPosition=position(p.point.x, p.point.y, p.point.z),
    )


def test_a_move_through_a_box_is_refused_and_nothing_moves(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    target = shifted(start, dx=0.2)
    sim.add_obstacle(box_at(shifted(start, dx=0.1)))
    before = sim.get_pose()
    with pytest.raises(Collision):
        sim.run_linear_positions([waypoint(target)], LINEAR)
    with pytest.raises(Collision):  # a JOINT move sweeps through it too
        sim.run_joint_positions([waypoint(target)], JointMotionParameters(velocity=50, acceleration=50))
    assert sim.get_pose() == before and sim.get_system_state() is SystemState.ACTIVE
    sim.remove_obstacle("box")
    sim.run_linear_positions([waypoint(target)], LINEAR)
    finish(sim, clock)
    assert np.allclose(sim.get_position().point.x, target.point.x, atol=1e-6)


def test_obstacles_are_kept_by_name_and_one_touching_the_moving_arm_is_refused(
    sim: SimController, clock: FakeClock
) -> None:
    here = sim.get_position()
    assert sim.add_obstacle(box_at(shifted(here, dx=0.3), name="a")) == "Obstacle 'a' added"
    sim.add_obstacle(box_at(shifted(here, dx=0.3, dy=0.2), name="b"))
    assert [o.name for o in sim.get_obstacles()] == ["a", "b"]
    sim.run_linear_positions([waypoint(shifted(here, dz=0.1))], LINEAR)  # moving: its queue ends above
    with pytest.raises(Collision, match="touches the arm or its tool while it moves"):
        sim.add_obstacle(box_at(shifted(here, dz=0.1), name="where it goes"))
    with pytest.raises(Collision, match="while it moves"):
        sim.add_obstacle(box_at(sim.get_position(), name="where it is"))
    assert [o.name for o in sim.get_obstacles()] == ["a", "b"]
    finish(sim, clock)
    # At rest, an obstacle on the flange is taken (the arm may back out of it), and the answer says so.
    added = sim.add_obstacle(box_at(sim.get_position(), name="on the flange"))
    assert added.startswith("Obstacle 'on the flange' added touching the arm (") and "link6" in added
    assert [o.name for o in sim.get_obstacles()] == ["a", "b", "on the flange"]
    with pytest.raises(PreconditionFailed, match="No obstacle named 'c'"):
        sim.get_obstacle("c")
    sim.remove_obstacles()
    assert sim.get_obstacles() == []


def test_the_tool_shape_takes_part_in_collision_checks(sim: SimController) -> None:
    here = sim.get_position()  # the tool points down
    sim.add_obstacle(box_at(shifted(here, dz=-0.15, dx=0.1), name="below", side=0.05))
    sim.run_linear_positions([waypoint(shifted(here, dx=0.1))], LINEAR)  # the bare flange passes above it
    sim.freeze()
    long_tool = ToolShape(
        shape=[
            SimplifiedCapsuleObstacle(radius=0.02, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.15))
        ]
    )
    sim.set_tool_shape(long_tool)
    with pytest.raises(Collision):
        sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.1))], LINEAR)
    floor_tool = ToolShape(
        shape=[
            SimplifiedCapsuleObstacle(radius=0.01, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.6))
        ]
    )
    with pytest.raises(Collision):
        sim.set_tool_shape(floor_tool)  # it would reach into the floor where the arm is
    assert sim.get_tool_shape() == long_tool


def _corner_run(sim: SimController, clock: FakeClock, blend: float) -> float:
    """Closest approach of the TCP to the corner waypoint of an L-shaped LINEAR run."""
    start = sim.get_position()
    corner = shifted(start, dx=0.1)
    end = shifted(corner, dy=0.1)
    sim.run_linear_positions([waypoint(corner, blend), waypoint(end)], LINEAR)
    path = record(sim, clock, dt=0.002).T[:, :3, 3]
    corner_xyz = np.array([corner.point.x, corner.point.y, corner.point.z])
    return float(np.min(np.linalg.norm(path - corner_xyz, axis=1)))


def test_a_waypoint_blend_rounds_the_corner_within_it(sim: SimController, clock: FakeClock) -> None:
    sharp = _corner_run(sim, clock, 0.0)
    sim.reset()
    rounded = _corner_run(sim, clock, 0.02)
    assert sharp <= DEFAULT_BLEND_TOL_M * SAMPLING_SLACK
    assert 5 * DEFAULT_BLEND_TOL_M < rounded <= 0.02


def test_a_blend_below_the_default_rounds_the_corner_tighter(sim: SimController, clock: FakeClock) -> None:
    default = _corner_run(sim, clock, 0.0)
    sim.reset()
    tight = _corner_run(sim, clock, DEFAULT_BLEND_TOL_M / 4)
    # Samples 2 ms apart miss the apex of so tight a turn by a little more than they miss a wide one's.
    assert tight <= DEFAULT_BLEND_TOL_M / 4 * 1.15 and tight < default / 2


def test_actions_run_when_their_waypoint_is_reached(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    first, second = shifted(start, dx=0.1), shifted(start, dx=0.2)
    set_do1 = OutputAction(target="output", port=1, value=SignalLevel.HIGH)
    close = GripperAction(target="gripper", value="CLOSE")
    sim.run_linear_positions([waypoint(first, actions=[set_do1]), waypoint(second, actions=[close])], LINEAR)
    seen = []
    while sim.get_system_state() is SystemState.MOTION:
        x = sim.get_position().point.x
        seen.append((x, sim.get_output(1), sim.gripper_opening()))
        clock.advance(0.01)
    low_x = [x for x, level, _ in seen if level is SignalLevel.LOW]
    high_x = [x for x, level, _ in seen if level is SignalLevel.HIGH]
    assert max(low_x) < first.point.x + DEFAULT_BLEND_TOL_M < min(high_x) + 0.01
    assert all(opening == 1.0 for _, _, opening in seen)  # closes only at the last waypoint
    assert sim.get_output(1) is SignalLevel.HIGH and sim.gripper_opening() == 0.0


def test_raw_interpolation_stops_at_every_waypoint(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    run = [waypoint(shifted(start, dx=0.05)), waypoint(shifted(start, dx=0.05, dy=0.05))]
    raw = LinearMotionParameters(interpolationType=InterpolationType.RAW, velocity=0.2, acceleration=1.0)
    sim.run_linear_positions(run, raw)
    speeds = record(sim, clock, dt=0.002).tcp_speed_m_s
    assert np.min(speeds[len(speeds) // 4 : 3 * len(speeds) // 4]) < 0.005  # at rest at the corner


def test_linear_acceleration_limits_how_fast_the_tcp_speeds_up(sim: SimController, clock: FakeClock) -> None:
    target = [waypoint(shifted(sim.get_position(), dx=0.2))]
    sim.run_linear_positions(target, LinearMotionParameters(velocity=0.5, acceleration=0.2))
    slow = finish(sim, clock, step=0.01)
    sim.reset()
    sim.run_linear_positions(target, LinearMotionParameters(velocity=0.5, acceleration=5.0))
    fast = finish(sim, clock, step=0.01)
    # 0.2 m at 0.2 m/s^2, never reaching 0.5 m/s: 2 sqrt(0.2 / 0.2) = 2 s
    assert slow == pytest.approx(2.0, abs=0.1) and fast < slow / 2


def test_protective_stop_holds_until_recover(sim: SimController, clock: FakeClock) -> None:
    sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.2))], LINEAR)
    clock.advance(0.3)
    sim.stop()
    held = sim.get_pose()
    clock.advance(2.0)
    assert sim.get_pose() == held and sim.get_system_state() is SystemState.ACTIVE
    with pytest.raises(PreconditionFailed, match="Protective stop"):
        sim.set_pose(held, MotionParams())
    assert sim.get_failures()[-1].type is FailureType.STOP_2
    assert sim.recover() is RecoverResult.SUCCESS
    sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.05))], LINEAR)
    assert sim.get_system_state() is SystemState.MOTION


def test_a_bound_input_stops_the_arm(sim: SimController, clock: FakeClock) -> None:
    sim.bind_stop(3, SignalLevel.HIGH)
    sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.2))], LINEAR)
    clock.advance(0.3)
    sim.set_input(3, SignalLevel.HIGH)
    held = sim.get_pose()
    clock.advance(1.0)
    assert sim.get_pose() == held
    assert "digital input 3 went HIGH" in sim.get_failures()[-1].message
    sim.recover()
    sim.unbind_stop()
    sim.set_input(3, SignalLevel.LOW)
    sim.set_input(3, SignalLevel.HIGH)
    sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.05))], LINEAR)
    assert sim.get_system_state() is SystemState.MOTION


def test_jogging_moves_the_tcp_that_way_until_a_zero_vector(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    sim.jog(JoggingVector(x=1.0))
    assert sim.get_system_state() is SystemState.JOGGING
    clock.advance(1.0)
    moved = sim.get_position()
    assert moved.point.x - start.point.x == pytest.approx(
        0.25 - 0.0625, abs=0.01
    )  # 0.5 m/s^2 ramp to 0.25 m/s
    assert abs(moved.point.y - start.point.y) < 1e-6 and abs(moved.point.z - start.point.z) < 1e-6
    sim.jog(JoggingVector())
    assert sim.get_system_state() is SystemState.ACTIVE
    held = sim.get_position()
    clock.advance(1.0)
    assert sim.get_position() == held


def test_jogging_stops_at_an_obstacle(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    sim.add_obstacle(box_at(shifted(start, dx=0.15), side=0.05))
    sim.jog(JoggingVector(x=1.0))
    finish(sim, clock, step=0.1)
    stopped = sim.get_position()
    assert 0.0 < stopped.point.x - start.point.x < 0.125
    assert sim.get_system_state() is SystemState.ACTIVE


def test_free_drive_lets_the_arm_be_moved_by_hand(sim: SimController) -> None:
    sim.zg_on()
    assert sim.get_system_state() is SystemState.ZERO_GRAVITY
    pose = sim.get_pose()
    moved = type(pose)(angles=[pose.angles[0] + 10, *pose.angles[1:]])
    sim.move_by_hand(moved)
    sim.zg_off()
    assert sim.get_system_state() is SystemState.ACTIVE and sim.get_pose() == moved


def test_a_disabled_gripper_refuses_to_move(sim: SimController) -> None:
    sim.disable_gripper()
    with pytest.raises(PreconditionFailed, match="gripper is disabled"):
        sim.close_gripper(250)
    close = GripperAction(target="gripper", value="CLOSE")
    with pytest.raises(PreconditionFailed, match="gripper is disabled"):
        sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.05), actions=[close])], LINEAR)
    assert sim.gripper_opening() == 1.0 and sim.get_system_state() is SystemState.ACTIVE
    sim.enable_gripper()
    sim.close_gripper(250)
    assert sim.get_system_state() is SystemState.MOTION


def test_twisted_refuses_motion_until_untwisting_is_finished(sim: SimController) -> None:
    sim.inject_fault(Fault.TWISTED)
    assert sim.get_system_state() is SystemState.TWISTED
    with pytest.raises(PreconditionFailed, match="twisted"):
        sim.run_linear_positions([waypoint(shifted(sim.get_position(), dx=0.05))], LINEAR)
    assert sim.finish_untwisting().startswith("Untwisting finished")
    assert sim.get_system_state() is SystemState.ACTIVE
    assert sim.finish_untwisting().startswith("The arm is not twisted")


def test_emergency_is_reported_by_status_and_failures(sim: SimController) -> None:
    sim.inject_fault(Fault.EMERGENCY)
    assert sim.get_system_state() is SystemState.EMERGENCY
    assert sim.get_failures()[-1].type is FailureType.EMCY
    sim.reset()
    assert sim.get_failures() == []
