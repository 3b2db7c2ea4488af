"""SDK 1.8.4: the tool's other views (/tool/info, /tool/shape) and the environment's obstacles.

Obstacle names travel in the path (URL-quoted by the SDK); an unknown name is 412 naming it.
"""

from __future__ import annotations

from enum import Enum
from typing import Annotated

from fastapi import APIRouter, Path, Request
from fastapi.concurrency import run_in_threadpool

from pendant.api import docs
from pendant.api.operation_route import body_of, serve
from pendant.api.params import read_body
from pendant.api.wire import JSONBytesResponse, TextResponse, model_result, models_result, string_result
from pendant.controller.cell_types import (
    MSG_NO_OBSTACLE,
    MSG_OBSTACLE_TOUCHES_ARM,
    MSG_PLANE_ON_A_LINE,
    MSG_SHAPE_TOUCHES,
    MSG_TOO_MANY_OBSTACLES,
    NAME_MAX_CHARS,
)
from pendant.controller.errors import MSG_COLLISION
from pendant.controller.protocol import Controller

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

    @serve(
        router,
        "GET /tool/info",
        summary="Getting the tool's name and TCP",
        description="The tool of GET /tool as SDK 1.8.4 sees it: its name, the TCP's pose from the flange.",
        ok="Tool name and TCP",
        example=EXAMPLE_TOOL_INFO,
        errors=docs.arm_errors(),
        tags=tool_tags,
    )
    async def get_tool_info() -> JSONBytesResponse:
        return model_result(controller.get_tool_info())

    @serve(
        router,
        "POST /tool/info",
        summary="Setting the tool's name and TCP",
        description="The same tool as POST /tool (its radius kept). Answers with the tool now in use.",
        ok="The tool now in use",
        example=EXAMPLE_TOOL_INFO,
        errors={**docs.bad_format(), **docs.precondition(MSG_COLLISION), **docs.arm_errors()},
        body_example=EXAMPLE_TOOL_INFO,
        body_description="Tool name and TCP",
        tags=tool_tags,
    )
    async def set_tool_info(request: Request) -> JSONBytesResponse:
        info = await read_body(request, body_of("POST /tool/info"))
        return model_result(await run_in_threadpool(controller.set_tool_info, info))

    @serve(
        router,
        "GET /tool/shape",
        summary="Getting the tool's shape",
        description="Capsules in the flange frame (metres), checked against obstacles and the floor.",
        ok="Tool shape",
        example=EXAMPLE_TOOL_SHAPE,
        errors=docs.arm_errors(),
        tags=tool_tags,
    )
    async def get_tool_shape() -> JSONBytesResponse:
        return model_result(controller.get_tool_shape())

    @serve(
        router,
        "POST /tool/shape",
        summary="Setting the tool's shape",
        description=(
            "Capsules in the flange frame, used in every collision check from now on. Refused (412) if they "
            "would touch an obstacle or the floor where the arm is or where its queued moves end."
        ),
        ok="The shape now in use",
        example=EXAMPLE_TOOL_SHAPE,
        errors={**docs.bad_format(), **docs.precondition(MSG_SHAPE_TOUCHES), **docs.arm_errors()},
        body_example=EXAMPLE_TOOL_SHAPE,
        body_description="Tool shape",
        tags=tool_tags,
    )
    async def set_tool_shape(request: Request) -> JSONBytesResponse:
        shape = await read_body(request, body_of("POST /tool/shape"))
        return model_result(await run_in_threadpool(controller.set_tool_shape, shape))

    env: list[str | Enum] = [docs.TAG_ENVIRONMENT]

    @serve(
        router,
        "PUT /environment",
        summary="Adding an obstacle",
        description=(
            "One BOX (sides, centerPosition), CAPSULE (radius, begin, finish) or PLANE (three points; the "
            "side away from the arm base is solid) per call, in the arm's base frame (metres, radians). "
            "An obstacle with a name already used replaces it. One that touches the resting arm is taken "
            "(the answer names the links): the arm may then move out of it, not deeper in. Refused (412) "
            "if it touches the arm while it moves (where it is or where its queued moves end)."
        ),
        ok="Done",
        example=["Obstacle 'table' added"],
        errors={
            **docs.bad_format(),
            **docs.precondition(MSG_OBSTACLE_TOUCHES_ARM, MSG_PLANE_ON_A_LINE, MSG_TOO_MANY_OBSTACLES),
            **docs.arm_errors(),
        },
        body_example=EXAMPLE_BOX,
        body_description="The obstacle",
        tags=env,
    )
    async def add_obstacle(request: Request) -> TextResponse:
        obstacle = await read_body(request, body_of("PUT /environment"))
        return string_result(await run_in_threadpool(controller.add_obstacle, obstacle))

    @serve(
        router,
        "GET /environment",
        summary="Getting every obstacle",
        ok="Obstacles",
        example=[EXAMPLE_BOX],
        errors=docs.arm_errors(),
        tags=env,
    )
    async def get_obstacles() -> JSONBytesResponse:
        return models_result(controller.get_obstacles())

    @serve(
        router,
        "DELETE /environment",
        summary="Removing every obstacle",
        ok="Done",
        example=["All obstacles removed"],
        errors=docs.arm_errors(),
        tags=env,
    )
    async def remove_obstacles() -> TextResponse:
        return string_result(controller.remove_obstacles())

    not_found = docs.precondition(MSG_NO_OBSTACLE.format(name="table"))

    @serve(
        router,
        "GET /environment/{obstacle}",
        summary="Getting an obstacle by name",
        ok="The obstacle",
        example=EXAMPLE_BOX,
        errors={**not_found, **docs.arm_errors()},
        convertors={"obstacle": "path"},
        tags=env,
    )
    async def get_obstacle(obstacle: NamePath) -> JSONBytesResponse:
        return model_result(controller.get_obstacle(obstacle))

    @serve(
        router,
        "DELETE /environment/{obstacle}",
        summary="Removing an obstacle by name",
        ok="Done",
        example=["Obstacle 'table' removed"],
        errors={**not_found, **docs.arm_errors()},
        convertors={"obstacle": "path"},
        tags=env,
    )
    async def remove_obstacle(obstacle: NamePath) -> TextResponse:
        return string_result(controller.remove_obstacle(obstacle))

    return router
