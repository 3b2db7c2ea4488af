"""GET/POST /base: the zero point, offset (metres, radians) from the physical centre of the arm base."""

from __future__ import annotations

from fastapi import APIRouter, Request

from pendant.api import docs
from pendant.api.params import POSITION, json_body, read_body
from pendant.api.wire import JSONBytesResponse, model_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.controller.protocol import Controller
from pendant.controller.types import Position

_BASE_DESCRIPTION = (
    "The zero point's offset from the physical centre of the arm base: x, y, z in metres, roll, pitch, yaw "
    "in radians."
)


def base_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Base"])

    @router.get(
        "/base",
        summary="Getting the actual position of the arm base",
        description=_BASE_DESCRIPTION,
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(Position, "Actual zero point", docs.EXAMPLE_BASE), **docs.arm_errors()},
    )
    async def get_base() -> JSONBytesResponse:
        return model_result(controller.get_base())

    @router.post(
        "/base",
        summary="Setting a new zero point position",
        description=_BASE_DESCRIPTION + " Answers with the zero point now in use.",
        response_class=JSONBytesResponse,
        responses={
            **docs.json_ok(Position, "The zero point now in use", docs.EXAMPLE_BASE),
            **docs.bad_format(),
            **docs.precondition(MSG_UNREACHABLE_POSITION, MSG_COLLISION),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("Position"), docs.EXAMPLE_BASE, "The new zero point"),
    )
    async def set_base(request: Request) -> JSONBytesResponse:
        base = await read_body(request, POSITION)
        return model_result(controller.set_base(base))

    return router
