"""SDK 1.8.4's operations, one suite for two Controllers: the simulator in-process and RemoteController over
the simulator's REST API. Both answer the same, down to the controller's messages."""

from __future__ import annotations

import pytest

from pendant.controller.cell_types import BoxObstacle, SimplifiedCapsuleObstacle, ToolInfo, ToolShape
from pendant.controller.errors import MSG_PROTECTIVE_STOP, Collision, PreconditionFailed
from pendant.controller.protocol import Controller
from pendant.controller.system_types import (
    FailureType,
    JoggingVector,
    JointMotionParameters,
    LinearMotionParameters,
    OutputAction,
    PoseWaypoint,
    PositionWaypoint,
    SystemState,
)
from pendant.controller.types import Point, Position, RecoverResult, Rotation, SignalLevel
from pendant.sim import FakeClock, Fault, SimController

LONG_ENOUGH_S = 60.0
LINEAR = LinearMotionParameters(velocity=0.3, acceleration=1.0)


def beside(controller: Controller, dy: float, actions: list | None = None) -> PositionWaypoint:
    here = controller.get_position()
    point = Point(x=here.point.x, y=here.point.y + dy, z=here.point.z)
    return PositionWaypoint(point=point, rotation=here.rotation, actions=actions)


def test_identity_and_state(controller: Controller, sim: SimController) -> None:
    assert controller.get_system_state() is SystemState.ACTIVE
    assert controller.get_robot_info() == sim.get_robot_info()
    assert controller.get_hardware_version() == sim.get_hardware_version()
    assert controller.get_software_version() == sim.get_software_version()
    assert controller.get_robot_software_version() == "1.8.2"
    assert controller.read_motors_log() == 6


def test_tool_info_shape_and_environment(controller: Controller) -> None:
    tcp = Position(point=Point(x=0, y=0, z=0.05), rotation=Rotation(roll=0, pitch=0, yaw=0))
    assert controller.set_tool_info(ToolInfo(name="cup", tcp=tcp)) == ToolInfo(name="cup", tcp=tcp)
    assert controller.get_tool().name == "cup"
    shape = ToolShape(
        shape=[
            SimplifiedCapsuleObstacle(radius=0.02, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.05))
        ]
    )
    assert controller.set_tool_shape(shape) == shape == controller.get_tool_shape()
    target = beside(controller, 0.2)
    centre = Position(
        point=Point(x=target.point.x, y=target.point.y - 0.1, z=target.point.z), rotation=tcp.rotation
    )
    box = BoxObstacle(
        obstacleType="BOX", name="a b/c", sides=Point(x=0.05, y=0.05, z=0.05), centerPosition=centre
    )
    assert controller.add_obstacle(box) == "Obstacle 'a b/c' added"
    assert controller.get_obstacles() == [box] and controller.get_obstacle("a b/c") == box
    with pytest.raises(Collision):
        controller.run_linear_positions([target], LINEAR)
    assert controller.remove_obstacle("a b/c") == "Obstacle 'a b/c' removed"
    with pytest.raises(PreconditionFailed, match="No obstacle named"):
        controller.remove_obstacle("a b/c")
    assert controller.remove_obstacles() == "All obstacles removed"


def test_runs_and_actions(controller: Controller, clock: FakeClock) -> None:
    set_do2 = OutputAction(target="output", port=2, value=SignalLevel.HIGH)
    assert controller.run_linear_positions([beside(controller, 0.05, [set_do2])], LINEAR) == "Motion accepted"
    clock.advance(LONG_ENOUGH_S)
    assert controller.get_output(2) is SignalLevel.HIGH
    joint = JointMotionParameters(velocity=50, acceleration=50)
    pose = controller.get_pose()
    turned = PoseWaypoint(angles=[pose.angles[0] + 10, *pose.angles[1:]])
    controller.run_joint_poses([turned], joint)
    clock.advance(LONG_ENOUGH_S)
    assert controller.get_pose().angles[0] == pytest.approx(pose.angles[0] + 10)
    controller.run_linear_poses([PoseWaypoint(angles=pose.angles)], LINEAR)
    clock.advance(LONG_ENOUGH_S)
    controller.run_joint_positions([beside(controller, -0.05)], joint)
    assert controller.get_system_state() is SystemState.MOTION


def test_stop_bind_free_drive_gripper_jog(
    controller: Controller, sim: SimController, clock: FakeClock
) -> None:
    assert controller.stop() == MSG_PROTECTIVE_STOP
    with pytest.raises(PreconditionFailed, match="Protective stop"):
        controller.jog(JoggingVector(z=1))
    assert controller.get_failures()[-1].type is FailureType.STOP_2
    assert controller.recover() is RecoverResult.SUCCESS
    controller.bind_stop(2, SignalLevel.LOW)
    controller.unbind_stop()
    controller.zg_on()
    assert controller.get_system_state() is SystemState.ZERO_GRAVITY
    controller.zg_off()
    controller.disable_gripper()
    with pytest.raises(PreconditionFailed, match="disabled"):
        controller.open_gripper(100)
    controller.enable_gripper()
    assert controller.jog(JoggingVector(z=0.5)) == "Jogging"
    assert controller.get_system_state() is SystemState.JOGGING
    assert controller.jog(JoggingVector()) == "Jogging stopped"
    sim.inject_fault(Fault.TWISTED)
    assert controller.finish_untwisting() == "Untwisting finished: the arm is ready"
