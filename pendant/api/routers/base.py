"""GET/POST /base: the zero point, offset (metres, radians) from the physical centre of the arm base."""

from __future__ import annotations

from fastapi import APIRouter, Request

from pendant.api import docs
from pendant.api.operation_route import body_of, serve
from pendant.api.params import read_body
from pendant.api.wire import JSONBytesResponse, model_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.controller.protocol import Controller

_BASE_DESCRIPTION = (
    "The zero point's offset from the physical centre of the arm base: x, y, z in metres, roll, pitch, yaw "
    "in radians."
)


def base_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Base"])

    @serve(
        router,
        "GET /base",
        summary="Getting the actual position of the arm base",
        description=_BASE_DESCRIPTION,
        ok="Actual zero point",
        example=docs.EXAMPLE_BASE,
        errors=docs.arm_errors(),
    )
    async def get_base() -> JSONBytesResponse:
        return model_result(controller.get_base())

    @serve(
        router,
        "POST /base",
        summary="Setting a new zero point position",
        description=_BASE_DESCRIPTION + " Answers with the zero point now in use.",
        ok="The zero point now in use",
        example=docs.EXAMPLE_BASE,
        errors={
            **docs.bad_format(),
            **docs.precondition(MSG_UNREACHABLE_POSITION, MSG_COLLISION),
            **docs.arm_errors(),
        },
        body_example=docs.EXAMPLE_BASE,
        body_description="The new zero point",
    )
    async def set_base(request: Request) -> JSONBytesResponse:
        base = await read_body(request, body_of("POST /base"))
        return model_result(controller.set_base(base))

    return router
