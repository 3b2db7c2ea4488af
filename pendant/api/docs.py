"""OpenAPI pieces shared by the routers: each endpoint's documented responses and errors, examples, tags."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel

from pendant.api import errors as api_errors
from pendant.api.wire import JSON, TEXT, text_literal

__all__ = ["JSON", "MSG_NOT_RESPONDING", "TEXT"]
from pendant.controller.errors import (
    MSG_BAD_FORMAT,
    MSG_COLLISION,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
)

Responses = dict[int | str, dict[str, Any]]

TAG_SIM = "Simulator only"
TAG_SYSTEM = "System (SDK 1.8)"
TAG_ENVIRONMENT = "Environment (SDK 1.8)"
TAG_SAFETY = "Stop, free drive, jogging (SDK 1.8)"
TAG_RUN = "Run (SDK 1.8)"

TAGS: list[dict[str, str]] = [
    {"name": "Position", "description": "The TCP position: metres and radians, relative to the zero point."},
    {"name": "Pose", "description": "The six servo flange angles, in degrees, base first."},
    {"name": "Status", "description": "Motion status and servo telemetry."},
    {"name": "Tool", "description": "The work tool and the TCP offset it defines."},
    {"name": "Base", "description": "The zero point (base) position in the user's environment."},
    {"name": "Robot", "description": "Identity and state commands: relax, freeze, recover, pack."},
    {"name": "Gripper", "description": "Opening and closing the gripper."},
    {"name": "Signals", "description": "Digital outputs 1-2 (relays) and inputs 1-4 on the control box."},
    {
        "name": TAG_SYSTEM,
        "description": (
            "Rozum's SDK 1.8.4: robot state and recent failures, model and serial numbers, versions, the "
            "motors' logs, untwisting."
        ),
    },
    {
        "name": TAG_ENVIRONMENT,
        "description": (
            "Rozum's SDK 1.8.4: box, capsule and plane obstacles, kept by name and checked along the whole "
            "path of every motion, with the tool's shape (capsules on the flange)."
        ),
    },
    {
        "name": TAG_SAFETY,
        "description": (
            "Rozum's SDK 1.8.4: the protective stop and its binding to digital inputs, free drive (zero "
            "gravity), jogging by an acceleration vector."
        ),
    },
    {
        "name": TAG_RUN,
        "description": (
            "Rozum's SDK 1.8.4: runs through waypoints with BLEND, SPLINE or RAW interpolation; linear "
            "velocity and acceleration in m/s and m/s^2, joint ones in percent; per-waypoint `blend` "
            "(metres for positions, degrees for poses) and `actions` (set an output, open or close the "
            "gripper when the waypoint is reached)."
        ),
    },
    {
        "name": TAG_SIM,
        "description": (
            "Not part of the PULSE API: controls of the embedded simulator (mounted only when the pendant "
            "serves its simulator), to play the outside world in tests and demos."
        ),
    },
]

EXAMPLE_POSITION = {
    "point": {"x": 0.3, "y": -0.2, "z": 0.4},
    "rotation": {"roll": 3.14159, "pitch": 0.0, "yaw": 0.0},
}
EXAMPLE_POSE = {"angles": [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]}
EXAMPLE_TOOL = {
    "name": "gripper",
    "point": {"x": 0.0, "y": 0.0, "z": 0.12},
    "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
    "radius": 0.05,
}
EXAMPLE_BASE = {
    "point": {"x": 0.0, "y": 0.0, "z": 0.0},
    "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
}
EXAMPLE_MOTOR = {
    "angle": 168.89699,
    "rotorVelocity": -0.00064343837,
    "rmsCurrent": 0.01,
    "voltage": 47.795017,
    "phaseCurrent": 0.01,
    "statorTemperature": 27.990631,
    "servoTemperature": 31.739925,
    "velocityError": -0.022674553,
    "velocitySetpoint": -0.02331799,
    "velocityOutput": 0.01,
    "velocityFeedback": -0.00064343837,
    "positionError": 0.0385437,
    "positionSetpoint": 168.93799,
    "positionOutput": 0.01,
    "positionFeedback": 168.89944,
}

MOTION_PARAMETER_MESSAGES = (
    api_errors.MSG_SPEED,
    api_errors.MSG_TYPE,
    api_errors.MSG_TCP_MAX_VELOCITY,
    api_errors.MSG_VELOCITY,
    api_errors.MSG_ACCELERATION,
)

WIRE_NOTE = (
    " String results and error messages are `text/plain` bodies holding a JSON string literal, quotes "
    'included (`"IDLE"`).'
)


def error(status: int, description: str, *messages: str) -> Responses:
    """One documented error status with the plain-text messages it can carry."""
    examples = {
        message: {"summary": message, "value": text_literal(message).decode()} for message in messages
    }
    return {
        status: {
            "description": description,
            "content": {TEXT: {"schema": {"type": "string"}, "examples": examples}},
        }
    }


def bad_format() -> Responses:
    return error(400, "Message parsing error", MSG_BAD_FORMAT)


def precondition(*messages: str) -> Responses:
    return error(412, "Incorrect input parameters", *messages)


def arm_errors() -> Responses:
    return {
        **error(500, "Arm error", MSG_NOT_RESPONDING),
        **error(503, "Arm emergency", MSG_EMERGENCY),
    }


def position_errors() -> Responses:
    return precondition(MSG_UNREACHABLE_POSITION, MSG_COLLISION, *MOTION_PARAMETER_MESSAGES)


def pose_errors() -> Responses:
    return precondition(MSG_UNREACHABLE_POSE, MSG_COLLISION, *MOTION_PARAMETER_MESSAGES)


def json_ok(model: type[BaseModel] | Any, description: str, example: Any) -> Responses:
    """A 200 carrying a JSON document (`model` may be a pydantic model or `list[Model]`)."""
    return {200: {"description": description, "model": model, "content": {JSON: {"example": example}}}}


def text_ok(description: str, schema: dict[str, Any], *values: str) -> Responses:
    """A 200 carrying a string result (JSON string literal in text/plain)."""
    examples = {value: {"value": text_literal(value).decode()} for value in values}
    return {
        200: {
            "description": description + "." + WIRE_NOTE,
            "content": {TEXT: {"schema": schema, "examples": examples}},
        }
    }


def empty_ok(description: str = "Success (empty body)") -> Responses:
    return {
        200: {"description": description, "content": {TEXT: {"schema": {"type": "string", "maxLength": 0}}}}
    }


def text_result(description: str, *examples: str) -> Responses:
    """A 200 carrying the controller's message (a JSON string literal in text/plain)."""
    return text_ok(description, {"type": "string"}, *examples)


def stamped(example: dict[str, Any]) -> dict[str, Any]:
    return {**example, "timestamp": "2026-11-22T10:00:00.000+00:00"}


def ref(name: str) -> dict[str, str]:
    return {"$ref": f"#/components/schemas/{name}"}


def waypoints(name: str) -> dict[str, Any]:
    return {"type": "array", "items": ref(name), "minItems": 1}
