"""A user's script written with Rozum's SDK (PyPI pulse-api 1.5.0 + pdhttp 1.5.0).

Run by tests/api/test_sdk.py with .venv-sdk/bin/python (the SDK pins urllib3 1.24.2): `sdk_script.py URL`.
It drives the arm and prints, as JSON, what it read, for the test to check.
"""

import json
import sys
from typing import Any

from pulseapi import MT_LINEAR, RobotPulse, pose, position

host = sys.argv[1]
robot = RobotPulse(host)
report = {}


def position_as_dict(p: Any) -> dict[str, list[float]]:  # the SDK's Position (untyped)
    return {
        "point": [p.point.x, p.point.y, p.point.z],
        "rotation": [p.rotation.roll, p.rotation.pitch, p.rotation.yaw],
    }


report["identifier"] = robot.identifier()
report["start_pose"] = robot.get_pose().angles
start_position = robot.get_position()
report["start_position"] = position_as_dict(start_position)
report["status_motors_count"] = len(robot.status_motors())
report["motor_angle_0"] = robot.status_motors()[0].angle

# A pose with integer angles, at a given speed, then wait for it.
pose_target = [round(a) + 10 for a in report["start_pose"][:2]] + [round(a) for a in report["start_pose"][2:]]
robot.set_pose(pose(pose_target), speed=5)  # seconds: still moving when a starved machine (nice 19) asks
report["status_while_moving"] = robot.status_motion()
robot.await_motion(0.02)
report["pose_target"] = pose_target
report["pose_after_set_pose"] = robot.get_pose().angles

# Through waypoints to a last pose.
last_pose = [a - 5 for a in pose_target]
robot.run_poses([pose([a - 2 for a in pose_target]), pose(last_pose)], speed=100)
robot.await_motion(0.02)
report["run_poses_target"] = last_pose
report["pose_after_run_poses"] = robot.get_pose().angles

# A straight line down 3 cm with the later SDK's velocity/acceleration and motion type.
here = robot.get_position()
down = position(
    (here.point.x, here.point.y, here.point.z - 0.03),
    (here.rotation.roll, here.rotation.pitch, here.rotation.yaw),
)
robot.set_position(down, velocity=80, acceleration=80, motion_type=MT_LINEAR)
robot.await_motion(0.02)
report["set_position_target"] = position_as_dict(down)
report["position_after_set_position"] = position_as_dict(robot.get_position())

# Back up through a waypoint.
up = position(
    (here.point.x, here.point.y, here.point.z), (here.rotation.roll, here.rotation.pitch, here.rotation.yaw)
)
robot.run_positions([down, up], speed=100, tcp_max_velocity=1.0)
robot.await_motion(0.02)
report["run_positions_target"] = position_as_dict(up)
report["position_after_run_positions"] = position_as_dict(robot.get_position())

robot.close_gripper(timeout=100)
robot.open_gripper()
robot.await_motion(0.02)

robot.set_digital_output_high(1)
report["output_1_after_high"] = robot.get_digital_output(1)
report["output_2_untouched"] = robot.get_digital_output(2)
robot.set_digital_output_low(1)
report["output_1_after_low"] = robot.get_digital_output(1)
report["input_2"] = robot.get_digital_input(2)

robot.relax()
report["status_relaxed"] = robot.status_motion()
robot.freeze()
report["status_frozen"] = robot.status_motion()
report["recover"] = robot.recover()

new_base = position((0.1, -0.05, 0.02), (0.0, 0.0, 0.3))
report["change_base_answer"] = position_as_dict(robot.change_base(new_base))
report["base"] = position_as_dict(robot.get_base())

print(json.dumps(report))
