"""The motion states and the faults: what each state allows, and how the arm gets out of it."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest

from pendant.controller.cell_types import BoxObstacle, ToolInfo, ToolShape
from pendant.controller.errors import (
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    Emergency,
    NotResponding,
    PreconditionFailed,
)
from pendant.controller.protocol import Controller
from pendant.controller.system_types import (
    JoggingVector,
    JointMotionParameters,
    LinearMotionParameters,
    PoseWaypoint,
    PositionWaypoint,
)
from pendant.controller.types import MotionParams, MotionStatus, Point, Pose, RecoverResult, SignalLevel
from pendant.sim import DEFAULT_BASE, DEFAULT_TOOL, HOME_POSE_DEG, FakeClock, Fault, SimController
from tests.support.sim_sampling import finish, position

JOINT_50 = MotionParams(speed=50)
LINEAR = LinearMotionParameters(velocity=0.2, acceleration=1.0)
JOINT = JointMotionParameters(velocity=50, acceleration=50)
FAR_BOX = BoxObstacle(
    obstacleType="BOX", name="far", sides=Point(x=0.1, y=0.1, z=0.1), centerPosition=position(1.0, 1.0, 1.0)
)
TARGET = Pose(angles=[40.0, -70.0, 60.0, -100.0, -60.0, 30.0])
ELSEWHERE = Pose(angles=[10.0, -80.0, 70.0, -90.0, -80.0, 0.0])


def _every_controller_call(sim: SimController) -> dict[str, Callable[[], object]]:
    here = position(-0.4, -0.1, 0.5, roll=3.14)
    waypoint = PositionWaypoint(point=here.point, rotation=here.rotation)
    return {
        "get_position": sim.get_position,
        "get_pose": sim.get_pose,
        "get_motion_status": sim.get_motion_status,
        "get_motors": sim.get_motors,
        "get_tool": sim.get_tool,
        "get_base": sim.get_base,
        "get_robot_id": sim.get_robot_id,
        "get_output": lambda: sim.get_output(1),
        "get_input": lambda: sim.get_input(1),
        "set_position": lambda: sim.set_position(here, JOINT_50),
        "set_pose": lambda: sim.set_pose(TARGET, JOINT_50),
        "run_positions": lambda: sim.run_positions([here], JOINT_50),
        "run_poses": lambda: sim.run_poses([TARGET], JOINT_50),
        "open_gripper": lambda: sim.open_gripper(500),
        "close_gripper": lambda: sim.close_gripper(500),
        "pack": sim.pack,
        "relax": sim.relax,
        "freeze": sim.freeze,
        "recover": sim.recover,
        "set_output": lambda: sim.set_output(1, SignalLevel.HIGH),
        "set_tool": lambda: sim.set_tool(DEFAULT_TOOL),
        "set_base": lambda: sim.set_base(DEFAULT_BASE),
        # SDK 1.8.4
        "clock_time": sim.clock_time,
        "get_system_state": sim.get_system_state,
        "get_failures": sim.get_failures,
        "get_robot_info": sim.get_robot_info,
        "get_hardware_version": sim.get_hardware_version,
        "get_software_version": sim.get_software_version,
        "get_robot_software_version": sim.get_robot_software_version,
        "read_motors_log": sim.read_motors_log,
        "get_tool_info": sim.get_tool_info,
        "set_tool_info": lambda: sim.set_tool_info(ToolInfo(name="t", tcp=here)),
        "get_tool_shape": sim.get_tool_shape,
        "set_tool_shape": lambda: sim.set_tool_shape(ToolShape(shape=[])),
        "add_obstacle": lambda: sim.add_obstacle(FAR_BOX),
        "get_obstacles": sim.get_obstacles,
        "get_obstacle": lambda: sim.get_obstacle("far"),
        "remove_obstacles": sim.remove_obstacles,
        "remove_obstacle": lambda: sim.remove_obstacle("far"),
        "enable_gripper": sim.enable_gripper,
        "disable_gripper": sim.disable_gripper,
        "zg_on": sim.zg_on,
        "zg_off": sim.zg_off,
        "stop": sim.stop,
        "bind_stop": lambda: sim.bind_stop(1, SignalLevel.HIGH),
        "unbind_stop": sim.unbind_stop,
        "finish_untwisting": sim.finish_untwisting,
        "jog": lambda: sim.jog(JoggingVector(x=0.5)),
        "run_linear_positions": lambda: sim.run_linear_positions([waypoint], LINEAR),
        "run_linear_poses": lambda: sim.run_linear_poses([PoseWaypoint(angles=TARGET.angles)], LINEAR),
        "run_joint_positions": lambda: sim.run_joint_positions([waypoint], JOINT),
        "run_joint_poses": lambda: sim.run_joint_poses([PoseWaypoint(angles=TARGET.angles)], JOINT),
    }


# GET /status and /status/failure say EMERGENCY (and why) in EMERGENCY; the clock always answers.
ANSWER_IN_EMERGENCY = {"get_system_state", "get_failures", "clock_time"}


def test_the_simulator_is_a_controller(sim: SimController) -> None:
    assert isinstance(sim, Controller)
    protocol_methods = {name for name in vars(Controller) if not name.startswith("_")}
    assert protocol_methods == set(_every_controller_call(sim))


def test_power_on_is_idle_at_home(sim: SimController) -> None:
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == list(HOME_POSE_DEG)


def test_idle_running_idle(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    duration = sim.motions.queue[0].duration
    clock.advance(duration * 0.999)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    clock.advance(duration * 0.002)
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_relax_stops_and_lets_the_arm_be_moved_by_hand(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    clock.advance(0.3)
    stopped_at = sim.get_pose()
    sim.relax()
    assert sim.get_motion_status() is MotionStatus.ZERO_GRAVITY
    clock.advance(10.0)
    assert sim.get_pose() == stopped_at
    sim.move_by_hand(ELSEWHERE)
    assert sim.get_pose().angles == ELSEWHERE.angles
    assert sim.get_motion_status() is MotionStatus.ZERO_GRAVITY


def test_a_motion_command_in_zero_gravity_engages_the_motors_and_runs(
    sim: SimController, clock: FakeClock
) -> None:
    sim.relax()
    sim.set_pose(TARGET, JOINT_50)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish(sim, clock)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert np.allclose(sim.get_pose().angles, TARGET.angles)


def test_moving_by_hand_needs_zero_gravity(sim: SimController) -> None:
    with pytest.raises(PreconditionFailed) as info:
        sim.move_by_hand(ELSEWHERE)
    assert "ZERO_GRAVITY" in info.value.message
    assert sim.get_pose().angles == list(HOME_POSE_DEG)


def test_freeze_in_zero_gravity_holds_the_arm(sim: SimController) -> None:
    sim.relax()
    sim.freeze()
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_error_freezes_the_arm_refuses_motion_and_recovers(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    clock.advance(0.3)
    frozen_at = sim.get_pose()
    sim.inject_fault(Fault.ERROR)
    assert sim.get_motion_status() is MotionStatus.ERROR
    clock.advance(5.0)
    assert sim.get_pose() == frozen_at  # reads still answer
    for command in (
        lambda: sim.set_pose(TARGET, JOINT_50),
        sim.pack,
        lambda: sim.close_gripper(100),
        sim.relax,
    ):
        with pytest.raises(NotResponding):  # 500, "Arm error"
            command()
    sim.freeze()
    assert sim.get_motion_status() is MotionStatus.ERROR
    sim.set_output(2, SignalLevel.HIGH)  # the control box IO still works
    assert sim.recover() is RecoverResult.SUCCESS
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose() == frozen_at
    sim.set_pose(TARGET, JOINT_50)
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, TARGET.angles)


def test_recover_answers_by_state(sim: SimController, clock: FakeClock) -> None:
    assert sim.recover() is RecoverResult.SUCCESS  # IDLE already
    sim.set_pose(TARGET, JOINT_50)
    assert sim.recover() is RecoverResult.FAILED  # nothing to recover from while running
    assert sim.get_motion_status() is MotionStatus.RUNNING
    sim.relax()
    assert sim.recover() is RecoverResult.FAILED
    assert sim.get_motion_status() is MotionStatus.ZERO_GRAVITY


def test_motion_failed_stops_and_the_next_command_runs(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    sim.set_pose(ELSEWHERE, JOINT_50)
    clock.advance(0.3)
    stopped_at = sim.get_pose()
    sim.inject_fault(Fault.MOTION_FAILED)
    assert sim.get_motion_status() is MotionStatus.MOTION_FAILED
    clock.advance(10.0)
    assert sim.get_pose() == stopped_at
    sim.set_pose(TARGET, JOINT_50)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, TARGET.angles)
    sim.inject_fault(Fault.MOTION_FAILED)
    assert sim.recover() is RecoverResult.SUCCESS
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_emergency_answers_every_call_with_503_until_reset(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    clock.advance(0.3)
    sim.inject_fault(Fault.EMERGENCY)
    for name, call in _every_controller_call(sim).items():
        if name in ANSWER_IN_EMERGENCY:
            continue
        with pytest.raises(Emergency) as info:
            call()
        assert info.value.message == MSG_EMERGENCY, name
        assert info.value.status_code == 503
    sim.reset()
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == list(HOME_POSE_DEG)


def test_no_response_answers_every_call_with_500_until_reset(sim: SimController) -> None:
    sim.inject_fault(Fault.NO_RESPONSE)
    for name, call in _every_controller_call(sim).items():
        if name == "clock_time":
            continue
        with pytest.raises(NotResponding) as info:
            call()
        assert info.value.message == MSG_NOT_RESPONDING, name
    sim.reset()
    assert sim.get_motion_status() is MotionStatus.IDLE


def test_reset_restores_the_power_on_state(sim: SimController, clock: FakeClock) -> None:
    sim.set_output(1, SignalLevel.HIGH)
    sim.set_input(3, SignalLevel.HIGH)
    sim.set_tool(DEFAULT_TOOL.model_copy(update={"name": "gripper", "radius": 0.05}))
    sim.set_base(position(0.1, 0.2, 0.0, yaw=0.5))
    sim.close_gripper(0)
    sim.set_pose(TARGET, JOINT_50)
    clock.advance(0.5)
    sim.reset()
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == list(HOME_POSE_DEG)
    assert sim.get_output(1) is SignalLevel.LOW and sim.get_input(3) is SignalLevel.LOW
    assert sim.get_tool() == DEFAULT_TOOL and sim.get_base() == DEFAULT_BASE
    assert sim.gripper_opening() == 1.0
    clock.advance(60.0)
    assert sim.get_pose().angles == list(HOME_POSE_DEG)  # nothing left in the queue
