"""GET/PUT /position and PUT /positions/run: the TCP position in metres and radians.

The moves are planned in a worker thread (IK and collision checks can take most of a second): on the event
loop they would hold up every other client, PUT /freeze included.
"""

from __future__ import annotations

from typing import Annotated, cast

from fastapi import APIRouter, Depends, Request
from fastapi.concurrency import run_in_threadpool

from pendant.api import docs
from pendant.api.operation_route import body_of, serve
from pendant.api.params import motion_params, read_body
from pendant.api.wire import JSONBytesResponse, TextResponse, empty_result, model_result, timestamped_result
from pendant.controller.protocol import Controller
from pendant.controller.types import MotionParams, Position

Params = Annotated[MotionParams, Depends(motion_params)]


def position_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Position"])

    @serve(
        router,
        "GET /position",
        summary="Getting the actual arm position",
        description=(
            "The TCP position: x, y, z (metres) from the zero point, and roll, pitch, yaw (radians, fixed "
            "axes x, y, z) relative to the zero point."
        ),
        ok="Actual arm position, with when it was read",
        example=docs.stamped(docs.EXAMPLE_POSITION),
        errors=docs.arm_errors(),
    )
    async def get_position() -> JSONBytesResponse:
        return timestamped_result(controller.get_position(), controller.clock_time())

    @serve(
        router,
        "PUT /position",
        summary="Setting a new arm position",
        description=(
            "Moves the TCP to a position: x, y, z in metres from the zero point, roll, pitch, yaw in "
            "radians. "
            "All six fields are required. Answers with the arm's position when the command was accepted."
        ),
        ok="Actual arm position",
        example=docs.EXAMPLE_POSITION,
        errors={**docs.bad_format(), **docs.position_errors(), **docs.arm_errors()},
        body_example=docs.EXAMPLE_POSITION,
        body_description="Target position (SDK 1.7's `blend` and `actions` allowed)",
    )
    async def set_position(request: Request, params: Params) -> JSONBytesResponse:
        target = await read_body(request, body_of("PUT /position"))
        return model_result(await run_in_threadpool(controller.set_position, target, params))

    @serve(
        router,
        "PUT /positions/run",
        summary="Asking the arm to move to a position",
        description=(
            "Moves the TCP smoothly through one or more positions (metres, radians) without stopping at "
            "the waypoints. All six fields of every waypoint are required."
        ),
        errors={**docs.bad_format(), **docs.position_errors(), **docs.arm_errors()},
        body_example=[docs.EXAMPLE_POSITION],
        body_description="Waypoints, each with an optional `blend` and `actions`",
    )
    async def run_positions(request: Request, params: Params) -> TextResponse:
        waypoints = await read_body(request, body_of("PUT /positions/run"))
        # A PositionWaypoint is a Position with a blend; the list is only read (so list's invariance does not
        # bite).
        await run_in_threadpool(controller.run_positions, cast(list[Position], waypoints), params)
        return empty_result()

    return router
