"""The PULSE API's data types, in the controller's units: metres and radians (positions), degrees (poses)."""

from __future__ import annotations

import math
from enum import StrEnum
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, field_validator

FiniteFloat = Annotated[float, Field(allow_inf_nan=False)]


class _Strict(BaseModel):
    # Missing fields are errors, extra ones are ignored, numbers must be numbers (no "1.0" strings).
    model_config = ConfigDict(strict=True, frozen=True)


class Point(_Strict):
    """Metres."""

    x: FiniteFloat
    y: FiniteFloat
    z: FiniteFloat


class Rotation(_Strict):
    """Radians, fixed axes: R = Rz(yaw) Ry(pitch) Rx(roll)."""

    roll: FiniteFloat
    pitch: FiniteFloat
    yaw: FiniteFloat


class Position(_Strict):
    """A TCP (or zero point) position: where and how it is turned."""

    point: Point
    rotation: Rotation


class Pose(_Strict):
    """The six servo flange angles in degrees, base first."""

    angles: Annotated[list[FiniteFloat], Field(min_length=6, max_length=6)]


TOOL_NAME_MAX = 128  # characters: a name, not a document (a 10 MB name cost the page a core, issue #16)


class Tool(_Strict):
    """The work tool: its name, the TCP offset from the flange, and its radius in metres."""

    name: Annotated[str, Field(max_length=TOOL_NAME_MAX)]
    point: Point
    rotation: Rotation
    radius: FiniteFloat

    @field_validator("radius")
    @classmethod
    def _radius_not_negative(cls, radius: float) -> float:
        if radius < 0 or not math.isfinite(radius):
            raise ValueError("radius must be a finite number >= 0")
        return radius

    @property
    def position(self) -> Position:
        return Position(point=self.point, rotation=self.rotation)


class MotorStatus(BaseModel):
    """One servo's telemetry, field names as the controller sends them."""

    model_config = ConfigDict(frozen=True)

    angle: float
    rotorVelocity: float
    rmsCurrent: float
    voltage: float
    phaseCurrent: float
    statorTemperature: float
    servoTemperature: float
    velocityError: float
    velocitySetpoint: float
    velocityOutput: float
    velocityFeedback: float
    positionError: float
    positionSetpoint: float
    positionOutput: float
    positionFeedback: float


class MotionStatus(StrEnum):
    IDLE = "IDLE"
    ZERO_GRAVITY = "ZERO_GRAVITY"
    RUNNING = "RUNNING"
    MOTION_FAILED = "MOTION_FAILED"
    EMERGENCY = "EMERGENCY"
    ERROR = "ERROR"


class SignalLevel(StrEnum):
    HIGH = "HIGH"
    LOW = "LOW"


class RecoverResult(StrEnum):
    SUCCESS = "SUCCESS"
    FAILED = "FAILED"


class MotionType(StrEnum):
    JOINT = "JOINT"
    LINEAR = "LINEAR"


class InterpolationType(StrEnum):
    """How a run goes through its waypoints (SDK 1.8.4's /run/* operations)."""

    BLEND = "BLEND"  # straight segments, each corner rounded within its waypoint's blend
    SPLINE = "SPLINE"  # joint runs: a smooth curve through every waypoint; linear: corners rounded widely
    RAW = "RAW"  # straight segments, stopping at every waypoint


# Speeds and accelerations are percent of the joint limits, exclusive of 0 as Rozum's SDK checks them;
# acceleration may go to 200 % (SDK >= 1.6).
SPEED_MIN, SPEED_MAX = 0.0, 100.0
ACCELERATION_MAX = 200.0
# A motion command that gives neither speed nor velocity (the SDK's own examples send only
# tcp_max_velocity) moves at this percentage of the joint speed limits.
DEFAULT_SPEED_PERCENT = 50.0
TCP_MAX_VELOCITY_MIN, TCP_MAX_VELOCITY_MAX = 0.0, 2.0
DEFAULT_GRIPPER_TIMEOUT_MS = 500
# The arm stays idle this long at most waiting for the gripper: a minute is far beyond any gripper, and a
# queue blocked for days by one command (2147483647 ms: 24.8 days) is a typo, not a wait.
GRIPPER_TIMEOUT_MAX_MS = 60_000
# The controller plans a run of at most this many waypoints (PUT /poses/run, /positions/run).
MAX_RUN_WAYPOINTS = 100
OUTPUT_PORTS = (1, 2)
INPUT_PORTS = (1, 2, 3, 4)


class MotionParams(BaseModel):
    """How to move: `speed` in percent of the joint limits, or the later SDK's `velocity` and `acceleration`
    (both percent). `tcp_max_velocity` caps the TCP speed in m/s. Ranges are checked by the API layer.
    The /run/* operations add `interpolation` and `tcp_acceleration` (m/s^2 along the TCP path)."""

    model_config = ConfigDict(frozen=True)

    speed: float = DEFAULT_SPEED_PERCENT
    motion_type: MotionType = MotionType.JOINT
    tcp_max_velocity: float = TCP_MAX_VELOCITY_MAX
    acceleration: float | None = None
    interpolation: InterpolationType | None = None
    tcp_acceleration: float | None = None
