"""One suite, two Controllers: the simulator in-process, and RemoteController talking to the simulator's
REST API (Starlette's TestClient is an httpx.Client, so no network). Both must behave the same, down to
the controller's messages; the remote one must also return exactly what the simulator holds."""

from __future__ import annotations

import pytest

from pendant.controller.errors import (
    MSG_COLLISION,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    Collision,
    Emergency,
    NotResponding,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.protocol import Controller
from pendant.controller.types import (
    MotionParams,
    MotionStatus,
    MotionType,
    Point,
    Pose,
    Position,
    RecoverResult,
    Rotation,
    SignalLevel,
    Tool,
)
from pendant.sim import HOME_POSE_DEG, PACK_POSE_DEG, FakeClock, Fault, SimController

ANGLE_TOL_DEG = 1e-6
POS_TOL_M = 1e-6
LONG_ENOUGH_S = 120.0  # any motion in these tests is over by then

PARAMS = MotionParams(speed=50.0)
TARGET = Pose(angles=[30.0, -80.0, 70.0, -80.0, -90.0, 10.0])
WAYPOINTS = [Pose(angles=[10.0, -85.0, 85.0, -90.0, -90.0, 0.0]), TARGET]
OUT_OF_LIMITS = Pose(angles=[0.0, -90.0, 90.0, -90.0, -90.0, 1000.0])
SELF_COLLISION = Pose(angles=[0.0, -90.0, 160.0, 0.0, 0.0, 0.0])
FAR_AWAY = Position(point=Point(x=10.0, y=0.0, z=0.5), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0))
GRIPPER = Tool(
    name="gripper",
    point=Point(x=0.0, y=0.0, z=0.12),
    rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
    radius=0.05,
)


def assert_pose_close(actual: Pose, expected: Pose | tuple[float, ...]) -> None:
    expected_angles = expected.angles if isinstance(expected, Pose) else list(expected)
    assert actual.angles == pytest.approx(expected_angles, abs=ANGLE_TOL_DEG)


def test_it_is_a_controller(controller: Controller) -> None:
    assert isinstance(controller, Controller)


def test_reads_give_the_simulators_state_exactly(controller: Controller, sim: SimController) -> None:
    assert controller.get_pose() == sim.get_pose()
    assert controller.get_position() == sim.get_position()
    assert controller.get_motors() == sim.get_motors()
    assert controller.get_tool() == sim.get_tool()
    assert controller.get_base() == sim.get_base()
    assert controller.get_robot_id() == sim.get_robot_id()
    assert controller.get_motion_status() is MotionStatus.IDLE
    assert len(controller.get_motors()) == 6
    assert_pose_close(controller.get_pose(), HOME_POSE_DEG)


def test_set_pose_moves_the_arm_there(controller: Controller, clock: FakeClock) -> None:
    controller.set_pose(TARGET, PARAMS)
    assert controller.get_motion_status() is MotionStatus.RUNNING
    clock.advance(LONG_ENOUGH_S)
    assert controller.get_motion_status() is MotionStatus.IDLE
    assert_pose_close(controller.get_pose(), TARGET)


def test_run_poses_ends_at_the_last_waypoint(controller: Controller, clock: FakeClock) -> None:
    controller.run_poses(WAYPOINTS, MotionParams(speed=80.0, motion_type=MotionType.JOINT))
    clock.advance(LONG_ENOUGH_S)
    assert_pose_close(controller.get_pose(), WAYPOINTS[-1])


def test_set_position_reaches_the_target(
    controller: Controller, clock: FakeClock, sim: SimController
) -> None:
    start = controller.get_position()
    target = Position(
        point=Point(x=start.point.x + 0.05, y=start.point.y, z=start.point.z - 0.05), rotation=start.rotation
    )
    assert controller.set_position(target, MotionParams(speed=50.0, motion_type=MotionType.LINEAR)) == start
    clock.advance(LONG_ENOUGH_S)
    reached = controller.get_position().point
    assert (reached.x, reached.y, reached.z) == pytest.approx(
        (target.point.x, target.point.y, target.point.z), abs=POS_TOL_M
    )
    assert controller.get_position() == sim.get_position()


def test_run_positions_through_waypoints(controller: Controller, clock: FakeClock) -> None:
    start = controller.get_position()
    waypoints = [
        Position(point=Point(x=start.point.x + dx, y=start.point.y, z=start.point.z), rotation=start.rotation)
        for dx in (0.02, 0.04)
    ]
    controller.run_positions(waypoints, PARAMS)
    clock.advance(LONG_ENOUGH_S)
    assert controller.get_position().point.x == pytest.approx(start.point.x + 0.04, abs=POS_TOL_M)


def test_an_unreachable_pose_is_refused_and_nothing_moves(controller: Controller) -> None:
    before = controller.get_pose()
    with pytest.raises(Unreachable) as caught:
        controller.set_pose(OUT_OF_LIMITS, PARAMS)
    assert caught.value.message == MSG_UNREACHABLE_POSE
    assert controller.get_motion_status() is MotionStatus.IDLE
    assert controller.get_pose() == before


def test_an_unreachable_position_is_refused(controller: Controller) -> None:
    with pytest.raises(Unreachable) as caught:
        controller.set_position(FAR_AWAY, PARAMS)
    assert caught.value.message == MSG_UNREACHABLE_POSITION


def test_a_self_collision_is_refused(controller: Controller) -> None:
    with pytest.raises(Collision) as caught:
        controller.set_pose(SELF_COLLISION, PARAMS)
    assert caught.value.message == MSG_COLLISION


def test_a_speed_out_of_range_is_a_precondition_failure(controller: Controller) -> None:
    with pytest.raises(PreconditionFailed, match="speed"):
        controller.set_pose(TARGET, MotionParams(speed=250.0))


def test_outputs_and_inputs(controller: Controller, sim: SimController) -> None:
    assert controller.get_output(2) is SignalLevel.LOW
    controller.set_output(2, SignalLevel.HIGH)
    assert controller.get_output(2) is SignalLevel.HIGH
    assert controller.get_output(1) is SignalLevel.LOW
    controller.set_output(2, SignalLevel.LOW)
    assert controller.get_output(2) is SignalLevel.LOW
    sim.set_input(3, SignalLevel.HIGH)
    assert controller.get_input(3) is SignalLevel.HIGH
    assert controller.get_input(4) is SignalLevel.LOW


def test_a_port_that_does_not_exist_is_a_precondition_failure(controller: Controller) -> None:
    with pytest.raises(PreconditionFailed, match="port"):
        controller.get_output(3)
    with pytest.raises(PreconditionFailed, match="port"):
        controller.get_input(5)


def test_tool_and_base_are_kept(controller: Controller) -> None:
    assert controller.set_tool(GRIPPER) == GRIPPER
    assert controller.get_tool() == GRIPPER
    base = Position(point=Point(x=0.1, y=-0.2, z=0.0), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.5))
    assert controller.set_base(base) == base
    assert controller.get_base() == base


def test_gripper_commands_take_their_timeout(controller: Controller, clock: FakeClock) -> None:
    controller.close_gripper(500)
    assert controller.get_motion_status() is MotionStatus.RUNNING
    clock.advance(1.0)
    controller.open_gripper(500)
    clock.advance(1.0)
    assert controller.get_motion_status() is MotionStatus.IDLE


def test_pack_goes_to_the_transport_pose(controller: Controller, clock: FakeClock) -> None:
    controller.pack()
    clock.advance(LONG_ENOUGH_S)
    assert_pose_close(controller.get_pose(), PACK_POSE_DEG)


def test_relax_and_freeze(controller: Controller, clock: FakeClock) -> None:
    controller.set_pose(TARGET, PARAMS)
    clock.advance(0.2)
    controller.relax()
    assert controller.get_motion_status() is MotionStatus.ZERO_GRAVITY
    controller.freeze()
    assert controller.get_motion_status() is MotionStatus.IDLE
    stopped = controller.get_pose()
    clock.advance(LONG_ENOUGH_S)
    assert controller.get_pose() == stopped  # the dropped motion does not resume


def test_an_error_is_recovered(controller: Controller, sim: SimController) -> None:
    sim.inject_fault(Fault.ERROR)
    assert controller.get_motion_status() is MotionStatus.ERROR
    with pytest.raises(NotResponding):
        controller.set_pose(TARGET, PARAMS)
    assert controller.recover() is RecoverResult.SUCCESS
    assert controller.get_motion_status() is MotionStatus.IDLE


def test_an_emergency_answers_every_call_with_its_message(controller: Controller, sim: SimController) -> None:
    sim.inject_fault(Fault.EMERGENCY)
    for call in (controller.get_pose, controller.get_motion_status, controller.relax, controller.recover):
        with pytest.raises(Emergency) as caught:
            call()
        assert caught.value.message == MSG_EMERGENCY


def test_a_controller_that_does_not_respond(controller: Controller, sim: SimController) -> None:
    sim.inject_fault(Fault.NO_RESPONSE)
    with pytest.raises(NotResponding) as caught:
        controller.get_position()
    assert caught.value.message == MSG_NOT_RESPONDING
    sim.reset()
    assert controller.get_motion_status() is MotionStatus.IDLE
