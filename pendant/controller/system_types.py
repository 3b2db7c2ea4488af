"""What Rozum's SDK 1.8.4 adds beyond the reference guide: system state, failures, identity, versions,
jogging, the /run/* motion parameters and waypoints carrying `blend` and `actions`."""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Literal

from pydantic import AliasChoices, BaseModel, ConfigDict, Field, field_validator

from pendant.controller.types import (
    OUTPUT_PORTS,
    FiniteFloat,
    InterpolationType,
    Pose,
    Position,
    SignalLevel,
)


class _Strict(BaseModel):
    model_config = ConfigDict(strict=True, frozen=True, populate_by_name=True)


class SystemState(StrEnum):
    INITIALIZING = "INITIALIZING"
    INITIALIZATION_FAILURE = "INITIALIZATION_FAILURE"
    TWISTED = "TWISTED"
    ACTIVE = "ACTIVE"
    MOTION = "MOTION"
    ZERO_GRAVITY = "ZERO_GRAVITY"
    JOGGING = "JOGGING"
    BROKEN = "BROKEN"
    EMERGENCY = "EMERGENCY"


class FailureType(StrEnum):
    SOFTWARE_ERROR = "SOFTWARE_ERROR"
    HARDWARE_ERROR = "HARDWARE_ERROR"
    STOP_2 = "STOP_2"
    STOP_1 = "STOP_1"
    STOP_0 = "STOP_0"
    EMCY = "EMCY"


class FailureLevel(StrEnum):
    FATAL = "FATAL"
    ERROR = "ERROR"
    WARN = "WARN"


class Failure(BaseModel):
    model_config = ConfigDict(frozen=True)

    type: FailureType
    message: str
    date: str  # ISO 8601, UTC
    level: FailureLevel


class RobotInfo(BaseModel):
    model_config = ConfigDict(frozen=True)

    model: str
    version: str
    controlBoxSerialNumber: str
    armSerialNumber: str


class Version(BaseModel):
    model_config = ConfigDict(frozen=True)

    motorsVersion: list[str]
    safetyVersion: str
    usbCanVersion: str
    wristVersion: str


Unit = Annotated[FiniteFloat, Field(ge=-1.0, le=1.0)]


class JoggingVector(_Strict):
    """Base-frame direction and strength of a jog, each component in [-1, 1]."""

    x: Unit = 0.0
    y: Unit = 0.0
    z: Unit = 0.0
    rx: Unit = 0.0
    ry: Unit = 0.0
    rz: Unit = 0.0


class JoggingAcceleration(_Strict):
    acceleration: JoggingVector


class OutputAction(_Strict):
    target: Literal["output"]
    port: FiniteFloat  # the SDK types it as a number
    value: SignalLevel

    @field_validator("port")
    @classmethod
    def _a_digital_output(cls, port: float) -> float:
        if port not in OUTPUT_PORTS:
            raise ValueError("port must be a digital output")
        return port


class GripperAction(_Strict):
    target: Literal["gripper"]
    value: Literal["OPEN", "CLOSE"]


RobotAction = Annotated[OutputAction | GripperAction, Field(discriminator="target")]
MAX_ACTIONS_PER_WAYPOINT = 8
Actions = Annotated[list[RobotAction], Field(max_length=MAX_ACTIONS_PER_WAYPOINT)]
Blend = Annotated[FiniteFloat, Field(ge=0.0, le=1.0)]


class PositionWaypoint(Position):
    """A position in a run: `blend` (m) rounds the corner within that distance; `actions` run there."""

    blend: Blend = 0.0
    actions: Actions | None = None


class PoseWaypoint(Pose):
    """A pose in a run: `blend` (degrees of joint travel) rounds the corner; `actions` run there."""

    blend: Annotated[FiniteFloat, Field(ge=0.0, le=180.0)] = 0.0
    actions: Actions | None = None


LINEAR_VELOCITY_MAX_M_S = 2.0
LINEAR_ACCELERATION_MAX_M_S2 = 20.0
JOINT_VELOCITY_MAX_PERCENT = 100.0
JOINT_ACCELERATION_MAX_PERCENT = 200.0


class LinearMotionParameters(_Strict):
    interpolationType: InterpolationType | None = Field(
        default=None, validation_alias=AliasChoices("interpolationType", "interpolation_type")
    )
    velocity: Annotated[FiniteFloat, Field(gt=0.0, le=LINEAR_VELOCITY_MAX_M_S)]  # m/s at the TCP
    acceleration: Annotated[FiniteFloat, Field(gt=0.0, le=LINEAR_ACCELERATION_MAX_M_S2)]  # m/s^2 at the TCP
    uniform: bool = True


class JointMotionParameters(_Strict):
    interpolation_type: InterpolationType | None = Field(
        default=None, validation_alias=AliasChoices("interpolation_type", "interpolationType")
    )
    velocity: Annotated[FiniteFloat, Field(gt=0.0, le=JOINT_VELOCITY_MAX_PERCENT)]  # % of joint limits
    acceleration: Annotated[FiniteFloat, Field(gt=0.0, le=JOINT_ACCELERATION_MAX_PERCENT)]  # %


MAX_RUN_WAYPOINTS = 100
PositionList = Annotated[list[PositionWaypoint], Field(min_length=1, max_length=MAX_RUN_WAYPOINTS)]
PoseList = Annotated[list[PoseWaypoint], Field(min_length=1, max_length=MAX_RUN_WAYPOINTS)]


class LinearPositions(_Strict):
    positions: PositionList
    motionParameters: LinearMotionParameters


class LinearPoses(_Strict):
    poses: PoseList
    motionParameters: LinearMotionParameters


class JointPositions(_Strict):
    positions: PositionList
    motionParameters: JointMotionParameters


class JointPoses(_Strict):
    poses: PoseList
    motionParameters: JointMotionParameters


class PoseTimestamp(Pose):
    """GET /pose in SDK >= 1.8: the pose and when it was read (ISO 8601, UTC)."""

    timestamp: str


class PositionTimestamp(Position):
    """GET /position in SDK >= 1.8: the position and when it was read (ISO 8601, UTC)."""

    timestamp: str
