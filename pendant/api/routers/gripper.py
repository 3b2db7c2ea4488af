"""PUT /gripper/open and /gripper/close."""

from __future__ import annotations

from fastapi import APIRouter

from pendant.api import docs
from pendant.api.errors import MSG_TIMEOUT
from pendant.api.operation_route import serve
from pendant.api.params import TimeoutQuery
from pendant.api.wire import TextResponse, empty_result, string_result
from pendant.controller.errors import MSG_GRIPPER_DISABLED
from pendant.controller.protocol import Controller
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS


def gripper_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Gripper"])
    responses = {
        **docs.precondition(MSG_TIMEOUT, MSG_GRIPPER_DISABLED),
        **docs.arm_errors(),
    }

    @serve(
        router,
        "PUT /gripper/open",
        summary="Ask the arm to open the gripper",
        description="Opens the gripper; the arm stays idle `timeout` milliseconds, waiting for it.",
        errors=responses,
    )
    async def open_gripper(timeout: TimeoutQuery = DEFAULT_GRIPPER_TIMEOUT_MS) -> TextResponse:
        controller.open_gripper(timeout)  # type: ignore[arg-type]  # whole ms by the query's bounds, as sent
        return empty_result()

    @serve(
        router,
        "PUT /gripper/close",
        summary="Asking the arm to close the gripper",
        description="Closes the gripper; the arm stays idle `timeout` milliseconds, waiting for it.",
        errors=responses,
    )
    async def close_gripper(timeout: TimeoutQuery = DEFAULT_GRIPPER_TIMEOUT_MS) -> TextResponse:
        controller.close_gripper(timeout)  # type: ignore[arg-type]  # whole ms by the query's bounds, as sent
        return empty_result()

    @serve(
        router,
        "POST /gripper/enable",
        summary="Powering the gripper on",
        description="SDK 1.8.4. The gripper works again (it is on at power-on).",
        ok="Done",
        example=["Gripper enabled"],
        errors=docs.arm_errors(),
    )
    async def enable_gripper() -> TextResponse:
        return string_result(controller.enable_gripper())

    @serve(
        router,
        "POST /gripper/disable",
        summary="Powering the gripper off",
        description=(
            "SDK 1.8.4. The gripper can be unplugged with the arm on; until POST /gripper/enable, opening "
            "or closing it (or a run with a gripper action) answers 412."
        ),
        ok="Done",
        example=["Gripper disabled: it may be unplugged"],
        errors=docs.arm_errors(),
    )
    async def disable_gripper() -> TextResponse:
        return string_result(controller.disable_gripper())

    return router
