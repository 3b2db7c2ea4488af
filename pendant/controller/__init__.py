"""The centre of the pendant: the Controller interface, its data types and errors (no FastAPI, no viser)."""

from pendant.controller.errors import (
    BadRequest,
    Collision,
    ControllerError,
    ControllerOffline,
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
    MotorStatus,
    Point,
    Pose,
    Position,
    RecoverResult,
    Rotation,
    SignalLevel,
    Tool,
)

__all__ = [
    "BadRequest",
    "Collision",
    "Controller",
    "ControllerError",
    "ControllerOffline",
    "Emergency",
    "MotionParams",
    "MotionStatus",
    "MotionType",
    "MotorStatus",
    "NotResponding",
    "Point",
    "Pose",
    "Position",
    "PreconditionFailed",
    "RecoverResult",
    "Rotation",
    "SignalLevel",
    "Tool",
    "Unreachable",
]
