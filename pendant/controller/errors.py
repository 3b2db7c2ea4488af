"""Typed controller errors. Each carries the controller's own message; the API maps them to status codes."""

from __future__ import annotations

from typing import ClassVar

MSG_BAD_FORMAT = "Incorrect format of input Message"
MSG_UNREACHABLE_POSITION = "Unreachable Position"
MSG_UNREACHABLE_POSE = "Unreachable Pose"
MSG_COLLISION = "Collision detected"
MSG_NOT_RESPONDING = "Robot does not respond"
MSG_EMERGENCY = "Robot unavailable in emergency state"
MSG_GRIPPER_DISABLED = "The gripper is disabled: POST /gripper/enable first"
MSG_PROTECTIVE_STOP = "Protective stop: the arm holds its position and refuses motion until PUT /recover"
MSG_JOG_BLOCKED = "Cannot jog that way: a joint limit, the workspace edge or an obstacle is right there"


class ControllerError(Exception):
    """A request the controller refused; `message` is its text, `status_code` its HTTP status."""

    status_code: ClassVar[int] = 500
    default_message: ClassVar[str] = MSG_NOT_RESPONDING

    def __init__(self, message: str | None = None) -> None:
        self.message = message if message is not None else self.default_message
        super().__init__(self.message)


class BadRequest(ControllerError):
    status_code = 400
    default_message = MSG_BAD_FORMAT


class PreconditionFailed(ControllerError):
    """412: the request is well formed but cannot be carried out (out of range, unreachable, collision)."""

    status_code = 412
    default_message = MSG_UNREACHABLE_POSITION


class Unreachable(PreconditionFailed):
    default_message = MSG_UNREACHABLE_POSITION


class Collision(PreconditionFailed):
    default_message = MSG_COLLISION


class NotResponding(ControllerError):
    status_code = 500
    default_message = MSG_NOT_RESPONDING


class Emergency(ControllerError):
    status_code = 503
    default_message = MSG_EMERGENCY


class ControllerOffline(ControllerError):
    """The pendant cannot reach the controller at all (connection refused, timeout, garbage answer)."""

    status_code = 502
    default_message = "Controller offline"


class Unsupported(ControllerOffline):
    """404: the controller does not know this operation (a firmware older than the SDK it is asked for)."""

    default_message = "The controller does not support this operation (older firmware)"


ERRORS_BY_STATUS: dict[int, type[ControllerError]] = {
    400: BadRequest,
    412: PreconditionFailed,
    500: NotResponding,
    503: Emergency,
}
