"""PULSE 1.8's `/run/*` operations as the runner's BlendedPath: a group of moves in one request, each
waypoint with its blend radius and its actions.

Recorded paths (Path steps) always go this way: `PUT /run/linear/positions` with interpolation BLEND, the
TCP at the path's speed and every corner rounded within half the step's tolerance. A controller that
answers 404 (firmware older than SDK 1.8) raises Unsupported; the executor then plays the path stop-and-go
(pendant.program.motion). Given to the runner as `blended=`, it sends every group this way, waypoint
actions included.
"""

from __future__ import annotations

from pendant.controller import Controller
from pendant.controller.errors import Unsupported
from pendant.controller.system_types import GripperAction as ApiGripperAction
from pendant.controller.system_types import (
    InterpolationType,
    JointMotionParameters,
    LinearMotionParameters,
    PoseWaypoint,
    PositionWaypoint,
)
from pendant.controller.system_types import OutputAction as ApiOutputAction
from pendant.controller.types import SPEED_MAX, MotionParams, MotionType, Pose
from pendant.program.geometry import MM
from pendant.program.models import GripperAction, OutputAction
from pendant.program.plan import MoveGroup, Target

# Along a recorded path the TCP speeds up and slows down at this rate (m/s^2), as jogging does; the
# controller still slows wherever a joint would exceed its own limits (tight corners).
PATH_ACCELERATION_M_S2 = 0.5
# A move's speed in percent, where a /run/linear call wants metres per second at the TCP: 100 % is 1 m/s.
LINEAR_M_S_AT_FULL_SPEED = 1.0
# A joint run's blend is degrees of joint travel; a move's blend is millimetres at the TCP. One degree of
# joint travel moves the TCP about this far at the PULSE's reach (0.5 m lever).
MM_PER_JOINT_DEGREE = 8.7

# A planned path's corners are rounded within this (degrees of joint travel): a thousandth of a degree, so
# the arm follows the straight joint segments the planner checked against the cell (a SPLINE through the
# same waypoints bulges off them, into what the planner went around).
PLANNED_CORNER_BLEND_DEG = 0.001

FALLBACK_NOTE = (
    "This controller has no /run/* operations (HTTP 404: firmware older than SDK 1.8): recorded paths "
    "play stop-and-go, one linear move per waypoint."
)


class BlendedRun:
    """Sends a MoveGroup as one `/run/*` request on `controller` (simulator or RemoteController alike).

    `supported`: None until the first request, then whether the controller has the operations."""

    def __init__(self, controller: Controller) -> None:
        self._controller = controller
        self.supported: bool | None = None

    def run_path(self, group: MoveGroup) -> None:
        try:
            self._send(group)
        except Unsupported:
            self.supported = False
            raise
        self.supported = True

    def _send(self, group: MoveGroup) -> None:
        controller, targets = self._controller, group.targets
        interpolation = InterpolationType.BLEND
        if group.by_angles:
            poses = [
                PoseWaypoint(
                    angles=list(t.expect_pose().angles),
                    blend=t.blend_mm / MM_PER_JOINT_DEGREE,
                    actions=_actions(t),
                )
                for t in targets
            ]
            if group.motion is MotionType.LINEAR:
                controller.run_linear_poses(poses, self._linear(group))
            else:
                controller.run_joint_poses(poses, _joint(group, interpolation))
            return
        positions = [
            PositionWaypoint(
                point=t.expect_position().point,
                rotation=t.expect_position().rotation,
                blend=t.blend_mm * MM,
                actions=_actions(t),
            )
            for t in targets
        ]
        if group.motion is MotionType.LINEAR:
            controller.run_linear_positions(positions, self._linear(group))
        else:
            controller.run_joint_positions(positions, _joint(group, interpolation))

    @staticmethod
    def _linear(group: MoveGroup) -> LinearMotionParameters:
        velocity = group.velocity_m_s
        if velocity is None:
            velocity = group.speed / SPEED_MAX * LINEAR_M_S_AT_FULL_SPEED
        return LinearMotionParameters(
            interpolationType=InterpolationType.BLEND,
            velocity=velocity,
            acceleration=PATH_ACCELERATION_M_S2,
        )


def run_planned_path(controller: Controller, poses: list[Pose], speed: float) -> None:
    """A path from the planner, as it was checked: straight joint segments with near-exact corners, in one
    `PUT /run/joint/poses` (BLEND). A controller without the /run/* operations (firmware older than SDK 1.8)
    gets `PUT /poses/run`, whose interpolation between the waypoints is the controller's own."""
    waypoints = [PoseWaypoint(angles=list(pose.angles), blend=PLANNED_CORNER_BLEND_DEG) for pose in poses]
    params = JointMotionParameters(
        interpolation_type=InterpolationType.BLEND, velocity=speed, acceleration=speed
    )
    try:
        controller.run_joint_poses(waypoints, params)
    except Unsupported:
        controller.run_poses(poses, MotionParams(speed=speed, motion_type=MotionType.JOINT))


def _joint(group: MoveGroup, interpolation: InterpolationType) -> JointMotionParameters:
    return JointMotionParameters(
        interpolation_type=interpolation, velocity=group.speed, acceleration=group.speed
    )


def _actions(target: Target) -> list[ApiOutputAction | ApiGripperAction] | None:
    """The waypoint's actions in the API's form (None: none, as the SDK leaves the field out)."""
    if not target.actions:
        return None
    return [
        ApiOutputAction(target="output", port=float(a.port), value=a.value)
        if isinstance(a, OutputAction)
        else ApiGripperAction(target="gripper", value="OPEN" if a.value is GripperAction.OPEN else "CLOSE")
        for a in target.actions
    ]
