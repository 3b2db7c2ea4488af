"""GET /robot/id and the state commands: PUT /relax, /freeze, /recover, /pack."""

from __future__ import annotations

from fastapi import APIRouter
from fastapi.concurrency import run_in_threadpool

from pendant.api import docs
from pendant.api.operation_route import serve
from pendant.api.wire import TextResponse, empty_result, string_result
from pendant.controller.errors import MSG_PROTECTIVE_STOP
from pendant.controller.protocol import Controller


def robot_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Robot"])

    @serve(
        router,
        "GET /robot/id",
        summary="Getting the arm ID",
        description="The arm's unique identifier, made of its servo motors' identifiers.",
        ok="Arm ID",
        example=["1346466AFG872"],
        errors=docs.arm_errors(),
    )
    async def get_robot_id() -> TextResponse:
        return string_result(controller.get_robot_id())

    @serve(
        router,
        "PUT /relax",
        summary="Asking the robot to relax",
        description="The arm stops without holding its position (ZERO_GRAVITY): it can be moved by hand.",
        errors={**docs.precondition(MSG_PROTECTIVE_STOP), **docs.arm_errors()},
    )
    async def relax() -> TextResponse:
        controller.relax()
        return empty_result()

    @serve(
        router,
        "PUT /freeze",
        summary="Asking the arm to go to the freeze state",
        description="The arm stops and holds its position. Do not move it by hand in this state.",
        errors=docs.arm_errors(),
    )
    async def freeze() -> TextResponse:
        controller.freeze()
        return empty_result()

    @serve(
        router,
        "PUT /recover",
        summary="Recovering the arm after an emergency",
        description=(
            "Brings the arm from ERROR back to IDLE. SUCCESS: recovered; FAILED: recovery failed. "
            "An EMERGENCY cannot be recovered."
        ),
        ok="Recover result",
        errors=docs.arm_errors(),
    )
    async def recover() -> TextResponse:
        return string_result(controller.recover().value)

    @serve(
        router,
        "PUT /pack",
        summary="Setting the arm into a transportation pose",
        description="Moves the arm to its preset transportation pose.",
        errors=docs.arm_errors(),
    )
    async def pack() -> TextResponse:
        await run_in_threadpool(controller.pack)  # it plans: not on the event loop (see pose.py)
        return empty_result()

    return router
