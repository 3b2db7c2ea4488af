"""SDK 1.8.4: GET /status, /status/failure, /robot/info, /version/*, and POST /motors-log.

GET /status and /status/failure answer in EMERGENCY too (200): Rozum's SDK README asks them why a script
failed (see pendant.api.availability).
"""

from __future__ import annotations

from fastapi import APIRouter

from pendant.api import docs
from pendant.api.operation_route import serve
from pendant.api.wire import (
    JSONBytesResponse,
    TextResponse,
    json_result,
    model_result,
    models_result,
    string_result,
)
from pendant.controller.protocol import Controller
from pendant.controller.system_types import SystemState

_STATE_SCHEMA = {"type": "string", "enum": [state.value for state in SystemState]}
EXAMPLE_FAILURE = {
    "type": "STOP_2",
    "message": "Protective stop (POST /stop)",
    "date": "2026-11-22T10:00:00.000+00:00",
    "level": "WARN",
}
EXAMPLE_VERSION = {
    "motorsVersion": ["2.9.14"] * 6,
    "safetyVersion": "1.7.3",
    "usbCanVersion": "1.3.0",
    "wristVersion": "1.5.1",
}
EXAMPLE_INFO = {
    "model": "PULSE75",
    "version": "2.1",
    "controlBoxSerialNumber": "CO12345678",
    "armSerialNumber": "AR12345678",
}


def system_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=[docs.TAG_SYSTEM])

    @serve(
        router,
        "GET /status",
        summary="Getting the actual robot state",
        description=(
            "INITIALIZING, INITIALIZATION_FAILURE, TWISTED, ACTIVE (ready, not moving), MOTION, "
            "ZERO_GRAVITY, JOGGING, BROKEN (failed: an ERROR, PUT /recover), EMERGENCY. A JSON string. "
            "Answers in EMERGENCY too (200), so a script can ask why it failed."
        ),
        errors={
            200: {
                "description": "Robot state (a JSON string)",
                "content": {docs.JSON: {"schema": _STATE_SCHEMA, "example": "ACTIVE"}},
            },
            **docs.error(500, "Arm error", docs.MSG_NOT_RESPONDING),
        },
        response_class=JSONBytesResponse,
    )
    async def get_status() -> JSONBytesResponse:
        return json_result(controller.get_system_state().value)

    @serve(
        router,
        "GET /status/failure",
        summary="Getting the recent failures",
        description=(
            "The failures the arm recently had, oldest first: type (SOFTWARE_ERROR, HARDWARE_ERROR, "
            "STOP_2, STOP_1, STOP_0, EMCY), level (FATAL, ERROR, WARN), message, date (ISO 8601, UTC). "
            "Answers in EMERGENCY too."
        ),
        ok="Recent failures",
        example=[EXAMPLE_FAILURE],
        errors=docs.error(500, "Arm error", docs.MSG_NOT_RESPONDING),
    )
    async def get_failures() -> JSONBytesResponse:
        return models_result(controller.get_failures())

    @serve(
        router,
        "GET /robot/info",
        summary="Getting the arm's model and serial numbers",
        ok="Model, version, serial numbers",
        example=EXAMPLE_INFO,
        errors=docs.arm_errors(),
    )
    async def get_robot_info() -> JSONBytesResponse:
        return model_result(controller.get_robot_info())

    @serve(
        router,
        "GET /version/hardware",
        summary="Getting the hardware versions",
        description="Of the motors (base first), the safety board, the USB-CAN adapter and the wrist.",
        ok="Hardware versions",
        example=EXAMPLE_VERSION,
        errors=docs.arm_errors(),
    )
    async def get_hardware_version() -> JSONBytesResponse:
        return model_result(controller.get_hardware_version())

    @serve(
        router,
        "GET /version/software",
        summary="Getting the firmware versions",
        description="Of the motors (base first), the safety board, the USB-CAN adapter and the wrist.",
        ok="Firmware versions",
        example=EXAMPLE_VERSION,
        errors=docs.arm_errors(),
    )
    async def get_software_version() -> JSONBytesResponse:
        return model_result(controller.get_software_version())

    @serve(
        router,
        "GET /version/software/robot",
        summary="Getting the robot control software version",
        ok="Version",
        example=["1.8.2"],
        errors=docs.arm_errors(),
    )
    async def get_robot_software_version() -> TextResponse:
        return string_result(controller.get_robot_software_version())

    @serve(
        router,
        "POST /motors-log",
        summary="Reading the motors' logs",
        description="Reads the logs of every motor; answers how many were read (a JSON number).",
        ok="Number of logs read",
        example=6,
        errors=docs.arm_errors(),
    )
    async def read_motors_log() -> JSONBytesResponse:
        return json_result(controller.read_motors_log())

    return router
