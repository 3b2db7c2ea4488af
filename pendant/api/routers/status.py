"""GET /status/motion and /status/motors."""

from __future__ import annotations

from fastapi import APIRouter

from pendant.api import docs
from pendant.api.operation_route import serve
from pendant.api.wire import JSONBytesResponse, TextResponse, motors_result, string_result
from pendant.controller.protocol import Controller


def status_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Status"])

    @serve(
        router,
        "GET /status/motion",
        summary="Getting the actual motion status",
        description=(
            "IDLE: ready, not moving. ZERO_GRAVITY: relaxed, can be moved by hand. RUNNING: moving. "
            "MOTION_FAILED: the motion settings were wrong. EMERGENCY: fatal failure, no recovery. "
            "ERROR: stopped and frozen; PUT /recover brings it back."
        ),
        ok="Motion status",
        errors=docs.arm_errors(),
    )
    async def get_motion_status() -> TextResponse:
        return string_result(controller.get_motion_status().value)

    @serve(
        router,
        "GET /status/motors",
        summary="Getting the actual status of servo motors",
        description=(
            "Six objects, base first: angle (degrees), rotorVelocity (RPM), rmsCurrent and phaseCurrent (A), "
            "voltage (V), statorTemperature and servoTemperature (degrees C), velocitySetpoint, "
            "velocityFeedback, velocityError (RPM), velocityOutput (A), positionSetpoint, positionFeedback, "
            "positionError (degrees), positionOutput (RPM)."
        ),
        ok="Motor status array",
        example=[docs.EXAMPLE_MOTOR],
        errors=docs.arm_errors(),
    )
    async def get_motors() -> JSONBytesResponse:
        return motors_result(controller.get_motors())

    return router
