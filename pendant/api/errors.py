"""Every error the API answers, mapped to a status code and a plain-text message in one place.

- A `ControllerError` carries its own status (400, 412, 500, 503, 502 for an unreachable real controller) and
  the controller's message.
- A body that does not parse (bad JSON, NaN/Infinity, a missing field, a wrong number of angles, a string
  where a number belongs, an empty waypoint list) is 400 "Incorrect format of input Message".
- A query or path parameter that is not a number or out of range is 412 ("Incorrect input parameters" in
  the reference) with a message naming the parameter and its range (`speed` is optional: see params.py).
- FastAPI's 422 never leaves the app: its validation errors are re-mapped here.
- Anything else that goes wrong inside the controller is what a client of the real one would see: 500 "Robot
  does not respond" (the exception still propagates to the server's log).
"""

from __future__ import annotations

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.responses import Response
from starlette.routing import Match

from pendant.api.wire import TextResponse, text_literal
from pendant.controller.errors import (
    MSG_BAD_FORMAT,
    BadRequest,
    ControllerError,
    NotResponding,
    PreconditionFailed,
)
from pendant.controller.types import (
    ACCELERATION_MAX,
    GRIPPER_TIMEOUT_MAX_MS,
    INPUT_PORTS,
    OUTPUT_PORTS,
    SPEED_MAX,
    SPEED_MIN,
    TCP_MAX_VELOCITY_MAX,
    TCP_MAX_VELOCITY_MIN,
)

MSG_SPEED = f"speed must be a number above {SPEED_MIN:g}, up to {SPEED_MAX:g} (percent of the maximum speed)"
MSG_VELOCITY = (
    f"velocity must be a number above {SPEED_MIN:g}, up to {SPEED_MAX:g} (percent of the maximum velocity)"
)
MSG_ACCELERATION = (
    f"acceleration must be a number above {SPEED_MIN:g}, up to {ACCELERATION_MAX:g} "
    "(percent of the maximum acceleration)"
)
MSG_TCP_MAX_VELOCITY = (
    f"tcp_max_velocity must be a number above {TCP_MAX_VELOCITY_MIN:g}, up to {TCP_MAX_VELOCITY_MAX:g} (m/s)"
)
MSG_TYPE = "type must be JOINT or LINEAR"
MSG_MOTION_TYPE = "motionType must be JOINT or LINEAR"
MSG_TIMEOUT = f"timeout must be a number of milliseconds from 0 to {GRIPPER_TIMEOUT_MAX_MS}"
MSG_OUTPUT_PORT = f"port must be a digital output: {' or '.join(map(str, OUTPUT_PORTS))}"
MSG_INPUT_PORT = f"port must be a digital input: {INPUT_PORTS[0]} to {INPUT_PORTS[-1]}"
MSG_FAULT = "fault must be error, emergency, no_response, motion_failed, overheat or twisted"

_PARAMETER_MESSAGES = {
    "speed": MSG_SPEED,
    "velocity": MSG_VELOCITY,
    "acceleration": MSG_ACCELERATION,
    "tcp_max_velocity": MSG_TCP_MAX_VELOCITY,
    "type": MSG_TYPE,
    "motionType": MSG_MOTION_TYPE,
    "timeout": MSG_TIMEOUT,
    "fault": MSG_FAULT,
}


class ParameterError(PreconditionFailed):
    """412: a query or path parameter is missing or out of range; the message names it."""


def _is_input_path(path: str) -> bool:
    return "/signal/input/" in path


def _parameter_message(name: str, path: str) -> str:
    if name == "port":
        return MSG_INPUT_PORT if _is_input_path(path) else MSG_OUTPUT_PORT
    return _PARAMETER_MESSAGES.get(name, f"{name} is invalid")


def error_for_validation(exc: RequestValidationError, path: str) -> ControllerError:
    """The controller error a FastAPI validation failure stands for (parameters first, then the body)."""
    for error in exc.errors():
        location = error.get("loc", ())
        if len(location) >= 2 and location[0] in ("query", "path"):
            return ParameterError(_parameter_message(str(location[1]), path))
    return BadRequest(MSG_BAD_FORMAT)


def error_response(error: ControllerError) -> Response:
    return TextResponse(text_literal(error.message), status_code=error.status_code)


async def _on_controller_error(_request: Request, exc: Exception) -> Response:
    assert isinstance(exc, ControllerError)
    return error_response(exc)


async def _on_validation_error(request: Request, exc: Exception) -> Response:
    assert isinstance(exc, RequestValidationError)
    return error_response(error_for_validation(exc, request.url.path))


async def _on_unexpected_error(_request: Request, _exc: Exception) -> Response:
    return error_response(NotResponding())


HTTP_METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS")


def allowed_methods(request: Request) -> list[str]:
    """Every method some route answers at this path (Starlette's 405 names only the first route's: GET
    /pose and PUT /pose are two routes, so PUT /pose's 405 said `Allow: GET`)."""
    routes = request.app.router.routes
    return [
        method
        for method in HTTP_METHODS
        if any(route.matches({**request.scope, "method": method})[0] is Match.FULL for route in routes)
    ]


async def _on_http_error(request: Request, exc: Exception) -> Response:
    # 404 unknown path, 405 wrong method: same plain-text shape as every other error.
    assert isinstance(exc, StarletteHTTPException)
    headers = dict(exc.headers or {})
    if exc.status_code == 405:
        headers["Allow"] = ", ".join(allowed_methods(request))
    return TextResponse(text_literal(str(exc.detail)), status_code=exc.status_code, headers=headers)


def install_error_handlers(app: FastAPI) -> None:
    app.add_exception_handler(ControllerError, _on_controller_error)
    app.add_exception_handler(RequestValidationError, _on_validation_error)
    app.add_exception_handler(StarletteHTTPException, _on_http_error)
    app.add_exception_handler(Exception, _on_unexpected_error)
