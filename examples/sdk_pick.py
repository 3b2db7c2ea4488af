"""Rozum's SDK (pulse-api 1.8.4): go to a pick pose, close the gripper, come back; refuse a move into a wall.

Usage: python examples/sdk_pick.py [URL]   (default: $PULSE_URL, else http://127.0.0.1:8081)
"""

from __future__ import annotations

import os
import sys

from pulseapi import PulseApiException, RobotPulse, pose

PICK = [90, -90, 90, -90, -90, 0]
START = [0, -90, 90, -90, -90, 0]


def main() -> None:
    url = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("PULSE_URL", "http://127.0.0.1:8081")
    robot = RobotPulse(url)
    robot.set_pose(pose(PICK), speed=30)
    robot.await_stop(asking_interval=0.05)
    robot.close_gripper(timeout=500)
    print("picked at", [round(a, 2) for a in robot.get_pose().angles])
    robot.set_pose(pose(START), speed=30)
    robot.await_stop(asking_interval=0.05)
    print("back at", [round(a, 2) for a in robot.get_pose().angles])
    try:
        robot.set_pose(pose([0, -90, 90, -90, -90, 1000]), speed=30)  # J6 far past its limit
    except PulseApiException as refused:
        print("refused:", refused.status, refused.body)  # the controller's own message


if __name__ == "__main__":
    main()
