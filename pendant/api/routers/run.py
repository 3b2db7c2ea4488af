"""SDK 1.8.4: PUT /run/linear/{positions,poses} and /run/joint/{positions,poses}, routes of their table rows
(method, path, body model and answer: pendant.controller.operations).

Planned in a worker thread, like every move (see pose.py).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from fastapi import APIRouter, Request
from fastapi.concurrency import run_in_threadpool

from pendant.api import docs
from pendant.api.operation_route import body_of, serve
from pendant.api.params import read_body
from pendant.api.wire import TextResponse, string_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSE, MSG_UNREACHABLE_POSITION
from pendant.controller.protocol import Controller

_POSITION = {
    "point": {"x": 0.3, "y": -0.2, "z": 0.4},
    "rotation": {"roll": 3.14159, "pitch": 0.0, "yaw": 0.0},
    "blend": 0.02,
    "actions": [{"target": "output", "port": 1, "value": "HIGH"}],
}
_POSE = {
    "angles": [0.0, -90.0, 90.0, -90.0, -90.0, 0.0],
    "blend": 0.0,
    "actions": [{"target": "gripper", "value": "CLOSE"}],
}
_LINEAR = {"interpolationType": "BLEND", "velocity": 0.2, "acceleration": 0.5, "uniform": True}
_JOINT = {"interpolation_type": "SPLINE", "velocity": 30, "acceleration": 30}


def run_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=[docs.TAG_RUN])

    def add(
        key: str,
        example: dict[str, Any],
        summary: str,
        description: str,
        unreachable: str,
        run: Callable[[Any], str],
    ) -> None:
        adapter = body_of(key)

        async def endpoint(request: Request) -> TextResponse:
            body = await read_body(request, adapter)
            return string_result(await run_in_threadpool(run, body))

        serve(
            router,
            key,
            summary=summary,
            description=description + " Answers when the motion is accepted; it runs in the background.",
            ok="Accepted",
            example=["Motion accepted"],
            errors={
                **docs.bad_format(),
                **docs.precondition(unreachable, MSG_COLLISION),
                **docs.arm_errors(),
            },
            body_example=example,
            body_description="Waypoints and motion parameters",
            name=key.partition(" /")[2].replace("/", "_"),
        )(endpoint)

    linear = "velocity (m/s) and acceleration (m/s^2) at the TCP"
    joint = "velocity and acceleration in percent of the joints' limits"
    add(
        "PUT /run/linear/positions",
        {"positions": [_POSITION], "motionParameters": _LINEAR},
        "Straight-line motion through positions",
        f"The TCP moves in straight lines through the positions, {linear}.",
        MSG_UNREACHABLE_POSITION,
        lambda b: controller.run_linear_positions(b.positions, b.motionParameters),
    )
    add(
        "PUT /run/linear/poses",
        {"poses": [_POSE], "motionParameters": _LINEAR},
        "Straight-line motion through poses",
        f"The TCP moves in straight lines to where each pose puts it, arriving in that pose, {linear}.",
        MSG_UNREACHABLE_POSE,
        lambda b: controller.run_linear_poses(b.poses, b.motionParameters),
    )
    add(
        "PUT /run/joint/positions",
        {"positions": [_POSITION], "motionParameters": _JOINT},
        "Joint-space motion through positions",
        f"The joints move (the TCP path is not straight) through the positions, {joint}.",
        MSG_UNREACHABLE_POSITION,
        lambda b: controller.run_joint_positions(b.positions, b.motionParameters),
    )
    add(
        "PUT /run/joint/poses",
        {"poses": [_POSE], "motionParameters": _JOINT},
        "Joint-space motion through poses",
        f"The joints move through the poses, {joint}.",
        MSG_UNREACHABLE_POSE,
        lambda b: controller.run_joint_poses(b.poses, b.motionParameters),
    )
    return router
