"""GET/POST /tool: the work tool (name, TCP offset in metres and radians, radius in metres)."""

from __future__ import annotations

from fastapi import APIRouter, Request

from pendant.api import docs
from pendant.api.params import TOOL, json_body, read_body
from pendant.api.wire import JSONBytesResponse, model_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSITION
from pendant.controller.protocol import Controller
from pendant.controller.types import TOOL_NAME_MAX, Tool

_TOOL_DESCRIPTION = (
    f"name: up to {TOOL_NAME_MAX} characters; point x, y, z (metres) and rotation roll, pitch, yaw "
    "(radians): the TCP of the tool; radius: the tool's radius in metres (>= 0)."
)


def tool_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Tool"])

    @router.get(
        "/tool",
        summary="Getting actual tool properties",
        description=_TOOL_DESCRIPTION,
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(Tool, "Actual tool properties", docs.EXAMPLE_TOOL), **docs.arm_errors()},
    )
    async def get_tool() -> JSONBytesResponse:
        return model_result(controller.get_tool())

    @router.post(
        "/tool",
        summary="Setting tool properties",
        description=_TOOL_DESCRIPTION + " Answers with the tool now in use.",
        response_class=JSONBytesResponse,
        responses={
            **docs.json_ok(Tool, "The tool now in use", docs.EXAMPLE_TOOL),
            **docs.bad_format(),
            **docs.precondition(MSG_UNREACHABLE_POSITION, MSG_COLLISION),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("Tool"), docs.EXAMPLE_TOOL, "The new tool"),
    )
    async def set_tool(request: Request) -> JSONBytesResponse:
        tool = await read_body(request, TOOL)
        return model_result(controller.set_tool(tool))

    return router
