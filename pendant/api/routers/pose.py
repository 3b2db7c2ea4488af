"""GET/PUT /pose and PUT /poses/run: the six servo angles in degrees.

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
from pendant.api.wire import JSONBytesResponse, TextResponse, empty_result, timestamped_result
from pendant.controller.protocol import Controller
from pendant.controller.types import MotionParams, Pose

Params = Annotated[MotionParams, Depends(motion_params)]


def pose_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Pose"])

    @serve(
        router,
        "GET /pose",
        summary="Getting the actual arm pose",
        description="The output flange angles of the six servos, in degrees, base first.",
        ok="Actual arm pose, with when it was read",
        example=docs.stamped(docs.EXAMPLE_POSE),
        errors=docs.arm_errors(),
    )
    async def get_pose() -> JSONBytesResponse:
        return timestamped_result(controller.get_pose(), controller.clock_time())

    @serve(
        router,
        "PUT /pose",
        summary="Setting a new arm pose",
        description="Moves the arm to a pose: six servo angles in degrees, base first (exactly six numbers).",
        errors={**docs.bad_format(), **docs.pose_errors(), **docs.arm_errors()},
        body_example=docs.EXAMPLE_POSE,
        body_description="Target pose (SDK 1.7's `blend` and `actions` allowed)",
    )
    async def set_pose(request: Request, params: Params) -> TextResponse:
        target = await read_body(request, body_of("PUT /pose"))
        await run_in_threadpool(controller.set_pose, target, params)
        return empty_result()

    @serve(
        router,
        "PUT /poses/run",
        summary="Asking the arm to move to a pose",
        description=(
            "Moves the arm smoothly through one or more poses (six angles in degrees each) without stopping "
            "at the waypoints."
        ),
        errors={**docs.bad_format(), **docs.pose_errors(), **docs.arm_errors()},
        body_example=[docs.EXAMPLE_POSE],
        body_description="Waypoints, each with an optional `blend` and `actions`",
    )
    async def run_poses(request: Request, params: Params) -> TextResponse:
        waypoints = await read_body(request, body_of("PUT /poses/run"))
        # A PoseWaypoint is a Pose with a blend; the list is only read (so list's invariance does not bite).
        await run_in_threadpool(controller.run_poses, cast(list[Pose], waypoints), params)
        return empty_result()

    return router
