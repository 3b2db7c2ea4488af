"""A scene for pre-flight tests: two waypoints either side of the home pose, and a box right in between."""

from __future__ import annotations

import numpy as np

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Pose
from pendant.kinematics import ArmModel
from pendant.program.models import GripperAction, GripperStep, MoveStep, Program, WaitStep, Waypoint
from pendant.sim import HOME_POSE_DEG
from pendant.sim.cell import DEFAULT_BASE

LEFT_DEG = (40.0, *HOME_POSE_DEG[1:])
RIGHT_DEG = (-40.0, *HOME_POSE_DEG[1:])
BOX_NAME = "fixture"


def waypoint(name: str, angles: tuple[float, ...]) -> Waypoint:
    # The recorded position is not used by JOINT moves to a waypoint's angles.
    return Waypoint(name=name, pose=Pose(angles=list(angles)), position=DEFAULT_BASE)


def swing_program() -> Program:
    """Left, gripper, right (through the home pose), wait, back left: ~12 s at 15 %."""
    return Program(
        name="swing",
        waypoints=(waypoint("left", LEFT_DEG), waypoint("right", RIGHT_DEG)),
        steps=(
            MoveStep(waypoint="left", speed=15.0),
            GripperStep(action=GripperAction.CLOSE, timeout_ms=300),
            MoveStep(waypoint="right", speed=15.0),
            WaitStep(ms=400),
            MoveStep(waypoint="left", speed=15.0),
        ),
    )


def box_in_the_way() -> BoxObstacle:
    """A 10 cm box where the flange passes at the home pose (J1 = 0), a little below it."""
    x, y, z = ArmModel.load("pulse75").fk(np.radians(HOME_POSE_DEG))[:3, 3]
    return BoxObstacle.model_validate(
        {
            "obstacleType": "BOX",
            "name": BOX_NAME,
            "sides": {"x": 0.1, "y": 0.1, "z": 0.1},
            "centerPosition": {
                "point": {"x": float(x), "y": float(y), "z": float(z) - 0.02},
                "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
            },
        }
    )
