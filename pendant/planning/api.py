"""`POST /pendant/plan`: a collision-free joint path to a target, for scripts; it moves nothing.

A pendant extension on the API port (under /pendant/, never forwarded to a controller). The cell, the tool and
the start (unless the body gives "from") are read from the controller as it is now; the answer's waypoints go
to PUT /run/joint/poses as they are (BLEND, near-zero corners: the segments the planner checked). One plan at
a time (a plan takes a core for up to its budget).
"""

from __future__ import annotations

import json
import threading

import numpy as np
from fastapi import APIRouter, Request, Response
from pydantic import ValidationError
from starlette.concurrency import run_in_threadpool

from pendant.api.docs import error
from pendant.api.errors import error_response
from pendant.api.json_body import load_json
from pendant.controller.errors import BadRequest, ControllerError, PreconditionFailed
from pendant.controller.protocol import Controller
from pendant.kinematics import ArmModel
from pendant.planning.joint_planner import MARGIN_M
from pendant.planning.live import plan_on
from pendant.planning.request import PlanRequest

PLAN_PATH = "/pendant/plan"
MAX_MESSAGE_CHARS = 300
MSG_BUSY = "another plan is being made; try again when it is done"
_DESCRIPTION = (
    'Body: {"target": {"angles": [six, degrees]}} or {"target": {"position": {"point": ..., '
    '"rotation": ...}}} '
    '(the controller\'s zero point frame and tool); optionally "from": {"angles": [...]} (default: where '
    'the arm is) and "budget_s" (default 1, at most 10). The path keeps '
    f"{MARGIN_M * 1e3:g} mm from the obstacles where it can and is re-checked every 0.5 degree per joint. "
    'Answer: {"waypoints": [{"angles": [...]}, ...], "planning_ms": ..., "length_deg": ...}: send the '
    "waypoints as one PUT /run/joint/poses (interpolation_type BLEND, blend 0.001 on each: the straight "
    "joint segments the planner checked; PUT /poses/run's own interpolation may cut into what the path "
    "goes around). It moves nothing. See docs/planning.md."
)
_EXAMPLE = {"target": {"angles": [60, -90, 90, -90, -90, 0]}, "budget_s": 1.0}


def _bad_request(problem: ValidationError | ValueError) -> Response:
    if isinstance(problem, ValidationError):
        first = problem.errors()[0]
        where = ".".join(str(part) for part in first["loc"])
        text = f"{where}: {first['msg']}" if where else str(first["msg"])
    else:
        text = str(problem)
    return error_response(BadRequest(text[:MAX_MESSAGE_CHARS]))


def plan_router(controller: Controller, arm: ArmModel) -> APIRouter:
    """A router with POST /pendant/plan for this controller and arm model."""
    router = APIRouter(tags=["pendant"])
    one_at_a_time = threading.Lock()

    @router.post(
        PLAN_PATH,
        summary="Plan a collision-free joint path to a target (moves nothing)",
        description=_DESCRIPTION,
        openapi_extra={
            "requestBody": {
                "required": True,
                "content": {
                    "application/json": {"schema": PlanRequest.model_json_schema(), "example": _EXAMPLE}
                },
            }
        },
        responses={
            200: {"description": "The path's waypoints (degrees), the planning time and the path's length"},
            **error(
                400, "Malformed body", "target.angles: List should have at least 6 items after validation"
            ),
            **error(
                412,
                "Cannot be planned",
                "the target itself is inside 'fixture'",
                "the start itself is inside 'fixture'",
                "no path found in 1 s",
            ),
            **error(429, "A plan is being made", MSG_BUSY),
        },
    )
    async def post_plan(request: Request) -> Response:
        try:
            body = PlanRequest.model_validate(load_json(await request.body()))  # depth checked first
        except (ValidationError, ValueError) as problem:
            return _bad_request(problem)
        return await run_in_threadpool(_plan, body)

    def _plan(body: PlanRequest) -> Response:
        if not one_at_a_time.acquire(blocking=False):
            return error_response(_Busy(MSG_BUSY))
        try:
            start_deg = body.start.angles if body.start is not None else None
            path = plan_on(controller, arm, body.target, start_deg=start_deg, budget_s=body.budget_s)
        except ControllerError as refused:
            return error_response(refused)
        finally:
            one_at_a_time.release()
        answer = {
            "waypoints": [{"angles": [round(a, 6) for a in np.degrees(q).tolist()]} for q in path.waypoints],
            "planning_ms": round(path.planning_s * 1e3, 3),
            "length_deg": round(float(np.degrees(path.length_rad)), 3),
            "margin_mm": round(path.margin_m * 1e3, 3),
        }
        return Response(json.dumps(answer), media_type="application/json")

    return router


class _Busy(PreconditionFailed):
    status_code = 429
