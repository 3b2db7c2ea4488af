"""PUT /gripper/open and /gripper/close."""

from __future__ import annotations

from fastapi import APIRouter

from pendant.api import docs
from pendant.api.errors import MSG_TIMEOUT
from pendant.api.params import TimeoutQuery
from pendant.api.wire import TextResponse, empty_result
from pendant.controller.protocol import Controller
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS


def gripper_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Gripper"])
    responses = {**docs.empty_ok(), **docs.precondition(MSG_TIMEOUT), **docs.arm_errors()}

    @router.put(
        "/gripper/open",
        summary="Ask the arm to open the gripper",
        description="Opens the gripper; the arm stays idle `timeout` milliseconds, waiting for it.",
        response_class=TextResponse,
        responses=responses,
    )
    async def open_gripper(timeout: TimeoutQuery = DEFAULT_GRIPPER_TIMEOUT_MS) -> TextResponse:
        controller.open_gripper(timeout)
        return empty_result()

    @router.put(
        "/gripper/close",
        summary="Asking the arm to close the gripper",
        description="Closes the gripper; the arm stays idle `timeout` milliseconds, waiting for it.",
        response_class=TextResponse,
        responses=responses,
    )
    async def close_gripper(timeout: TimeoutQuery = DEFAULT_GRIPPER_TIMEOUT_MS) -> TextResponse:
        controller.close_gripper(timeout)
        return empty_result()

    return router
