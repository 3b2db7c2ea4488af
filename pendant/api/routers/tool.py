"""GET/POST /tool: the work tool (name, TCP offset in metres and radians, radius in metres)."""

from __future__ import annotations

from fastapi import APIRouter, Request

from pendant.api import docs
from pendant.api.operation_route import body_of, serve
from pendant.api.params import read_body
from pendant.api.wire import JSONBytesResponse, model_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.controller.protocol import Controller
from pendant.controller.types import TOOL_NAME_MAX

_TOOL_DESCRIPTION = (
    f"name: up to {TOOL_NAME_MAX} characters; point x, y, z (metres) and rotation roll, pitch, yaw "
    "(radians): the TCP of the tool; radius: the tool's radius in metres (>= 0)."
)


def tool_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Tool"])

    @serve(
        router,
        "GET /tool",
        summary="Getting actual tool properties",
        description=_TOOL_DESCRIPTION,
        ok="Actual tool properties",
        example=docs.EXAMPLE_TOOL,
        errors=docs.arm_errors(),
    )
    async def get_tool() -> JSONBytesResponse:
        return model_result(controller.get_tool())

    @serve(
        router,
        "POST /tool",
        summary="Setting tool properties",
        description=_TOOL_DESCRIPTION + " Answers with the tool now in use.",
        ok="The tool now in use",
        example=docs.EXAMPLE_TOOL,
        errors={
            **docs.bad_format(),
            **docs.precondition(MSG_UNREACHABLE_POSITION, MSG_COLLISION),
            **docs.arm_errors(),
        },
        body_example=docs.EXAMPLE_TOOL,
        body_description="The new tool",
    )
    async def set_tool(request: Request) -> JSONBytesResponse:
        tool = await read_body(request, body_of("POST /tool"))
        return model_result(controller.set_tool(tool))

    return router
