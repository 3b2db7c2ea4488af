"""SDK 1.8.4: the tool's other views (/tool/info, /tool/shape) and the environment's obstacles.

Obstacle names travel in the path (URL-quoted by the SDK); an unknown name is 412 naming it.
"""

from __future__ import annotations

from enum import Enum
from typing import Annotated

from fastapi import APIRouter, Path, Request
from fastapi.concurrency import run_in_threadpool
from pydantic import TypeAdapter

from pendant.api import docs
from pendant.api.params import json_body, read_body
from pendant.api.wire import JSONBytesResponse, TextResponse, model_result, models_result, string_result
from pendant.controller.cell_types import (
    MSG_NO_OBSTACLE,
    MSG_OBSTACLE_TOUCHES_ARM,
    MSG_PLANE_ON_A_LINE,
    MSG_SHAPE_TOUCHES,
    MSG_TOO_MANY_OBSTACLES,
    NAME_MAX_CHARS,
    Obstacle,
    ToolInfo,
    ToolShape,
)
from pendant.controller.errors import MSG_COLLISION
from pendant.controller.protocol import Controller

TOOL_INFO = TypeAdapter(ToolInfo)
TOOL_SHAPE = TypeAdapter(ToolShape)
OBSTACLE: TypeAdapter[Obstacle] = TypeAdapter(Obstacle)

EXAMPLE_TOOL_INFO = {
    "name": "gripper",
    "tcp": {"point": {"x": 0.0, "y": 0.0, "z": 0.12}, "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}},
}
EXAMPLE_TOOL_SHAPE = {
    "shape": [
        {"radius": 0.04, "begin": {"x": 0.0, "y": 0.0, "z": 0.0}, "finish": {"x": 0.0, "y": 0.0, "z": 0.12}}
    ]
}
EXAMPLE_BOX = {
    "obstacleType": "BOX",
    "name": "table",
    "sides": {"x": 0.6, "y": 0.4, "z": 0.05},
    "centerPosition": {
        "point": {"x": 0.5, "y": 0.0, "z": 0.1},
        "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
    },
}
NamePath = Annotated[str, Path(max_length=NAME_MAX_CHARS, description="The obstacle's name.")]


def cell_router(controller: Controller) -> APIRouter:
    router = APIRouter()
    tool_tags: list[str | Enum] = ["Tool"]

    @router.get(
        "/tool/info",
        tags=tool_tags,
        summary="Getting the tool's name and TCP",
        description="The tool of GET /tool as SDK 1.8.4 sees it: its name, the TCP's pose from the flange.",
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(ToolInfo, "Tool name and TCP", EXAMPLE_TOOL_INFO), **docs.arm_errors()},
    )
    async def get_tool_info() -> JSONBytesResponse:
        return model_result(controller.get_tool_info())

    @router.post(
        "/tool/info",
        tags=tool_tags,
        summary="Setting the tool's name and TCP",
        description="The same tool as POST /tool (its radius kept). Answers with the tool now in use.",
        response_class=JSONBytesResponse,
        responses={
            **docs.json_ok(ToolInfo, "The tool now in use", EXAMPLE_TOOL_INFO),
            **docs.bad_format(),
            **docs.precondition(MSG_COLLISION),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("ToolInfo"), EXAMPLE_TOOL_INFO, "Tool name and TCP"),
    )
    async def set_tool_info(request: Request) -> JSONBytesResponse:
        info = await read_body(request, TOOL_INFO)
        return model_result(await run_in_threadpool(controller.set_tool_info, info))

    @router.get(
        "/tool/shape",
        tags=tool_tags,
        summary="Getting the tool's shape",
        description="Capsules in the flange frame (metres), checked against obstacles and the floor.",
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(ToolShape, "Tool shape", EXAMPLE_TOOL_SHAPE), **docs.arm_errors()},
    )
    async def get_tool_shape() -> JSONBytesResponse:
        return model_result(controller.get_tool_shape())

    @router.post(
        "/tool/shape",
        tags=tool_tags,
        summary="Setting the tool's shape",
        description=(
            "Capsules in the flange frame, used in every collision check from now on. Refused (412) if they "
            "would touch an obstacle or the floor where the arm is or where its queued moves end."
        ),
        response_class=JSONBytesResponse,
        responses={
            **docs.json_ok(ToolShape, "The shape now in use", EXAMPLE_TOOL_SHAPE),
            **docs.bad_format(),
            **docs.precondition(MSG_SHAPE_TOUCHES),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("ToolShape"), EXAMPLE_TOOL_SHAPE, "Tool shape"),
    )
    async def set_tool_shape(request: Request) -> JSONBytesResponse:
        shape = await read_body(request, TOOL_SHAPE)
        return model_result(await run_in_threadpool(controller.set_tool_shape, shape))

    env: list[str | Enum] = [docs.TAG_ENVIRONMENT]

    @router.put(
        "/environment",
        tags=env,
        summary="Adding an obstacle",
        description=(
            "One BOX (sides, centerPosition), CAPSULE (radius, begin, finish) or PLANE (three points; the "
            "side away from the arm base is solid) per call, in the arm's base frame (metres, radians). "
            "An obstacle with a name already used replaces it. One that touches the resting arm is taken "
            "(the answer names the links): the arm may then move out of it, not deeper in. Refused (412) "
            "if it touches the arm while it moves (where it is or where its queued moves end)."
        ),
        response_class=TextResponse,
        responses={
            **docs.text_result("Done", "Obstacle 'table' added"),
            **docs.bad_format(),
            **docs.precondition(MSG_OBSTACLE_TOUCHES_ARM, MSG_PLANE_ON_A_LINE, MSG_TOO_MANY_OBSTACLES),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("Obstacle"), EXAMPLE_BOX, "The obstacle"),
    )
    async def add_obstacle(request: Request) -> TextResponse:
        obstacle = await read_body(request, OBSTACLE)
        return string_result(await run_in_threadpool(controller.add_obstacle, obstacle))

    @router.get(
        "/environment",
        tags=env,
        summary="Getting every obstacle",
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(list[Obstacle], "Obstacles", [EXAMPLE_BOX]), **docs.arm_errors()},
    )
    async def get_obstacles() -> JSONBytesResponse:
        return models_result(controller.get_obstacles())

    @router.delete(
        "/environment",
        tags=env,
        summary="Removing every obstacle",
        response_class=TextResponse,
        responses={**docs.text_result("Done", "All obstacles removed"), **docs.arm_errors()},
    )
    async def remove_obstacles() -> TextResponse:
        return string_result(controller.remove_obstacles())

    not_found = docs.precondition(MSG_NO_OBSTACLE.format(name="table"))

    @router.get(
        "/environment/{obstacle:path}",
        tags=env,
        summary="Getting an obstacle by name",
        response_class=JSONBytesResponse,
        responses={**docs.json_ok(Obstacle, "The obstacle", EXAMPLE_BOX), **not_found, **docs.arm_errors()},
    )
    async def get_obstacle(obstacle: NamePath) -> JSONBytesResponse:
        return model_result(controller.get_obstacle(obstacle))

    @router.delete(
        "/environment/{obstacle:path}",
        tags=env,
        summary="Removing an obstacle by name",
        response_class=TextResponse,
        responses={**docs.text_result("Done", "Obstacle 'table' removed"), **not_found, **docs.arm_errors()},
    )
    async def remove_obstacle(obstacle: NamePath) -> TextResponse:
        return string_result(controller.remove_obstacle(obstacle))

    return router
