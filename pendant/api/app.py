"""create_app(controller): the PULSE REST API in front of any Controller (the simulator or a real arm)."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, get_args, get_origin

from fastapi import APIRouter, FastAPI
from fastapi.openapi.utils import get_openapi
from fastapi.routing import APIRoute
from fastapi_offline import FastAPIOffline
from pydantic import TypeAdapter

from pendant import __version__
from pendant.access.http_guard import AccessGuard, AccessRules
from pendant.api import docs
from pendant.api.availability import UnavailableFirst
from pendant.api.errors import install_error_handlers
from pendant.api.limits import BODY_LIMITS, BodySizeLimit, body_limit, too_large_message
from pendant.api.routers.base import base_router
from pendant.api.routers.cell import cell_router
from pendant.api.routers.gripper import gripper_router
from pendant.api.routers.pose import pose_router
from pendant.api.routers.position import position_router
from pendant.api.routers.robot import robot_router
from pendant.api.routers.run import run_router
from pendant.api.routers.safety import safety_router
from pendant.api.routers.signal import signal_router
from pendant.api.routers.status import status_router
from pendant.api.routers.system import system_router
from pendant.api.routers.tool import tool_router
from pendant.api.routing import DirectDispatch, direct_endpoints
from pendant.api.stop_notice import StopNotice
from pendant.controller.operations import OPERATIONS, Source
from pendant.controller.protocol import Controller
from pendant.controller.stops import StopBus
from pendant.eventlog import EventLog

if TYPE_CHECKING:
    from pendant.sim import SimController

DESCRIPTION = """\
The REST API of the Rozum Robotics PULSE controller, as in its API reference guide, served by the pendant
(from its simulator, or passed through to a real arm).

Units: metres and radians for positions (`x, y, z`, `roll, pitch, yaw`, fixed axes: R = Rz(yaw) Ry(pitch)
Rx(roll)); degrees for poses (six servo flange angles, base first).

Wire format: JSON documents are `application/json`. String results (motion status, signal levels, recover
result, robot ID) and every error message are `text/plain` bodies holding a JSON string literal, quotes
included: `"IDLE"`, `"Robot does not respond"`. Commands with nothing to return answer 200 with an empty body.

Errors: 400 "Incorrect format of input Message" (the body does not parse: bad JSON, NaN or Infinity, a
missing field, a wrong number of angles, an empty waypoint list); 412 for what cannot be done ("Unreachable
Position", "Unreachable Pose", "Collision detected") and for a query or path parameter that is missing or out
of range (the message names it and its range); 500 "Robot does not respond"; 503 "Robot unavailable in
emergency state".

Motion commands take `speed` (above 0 up to 100 %, default 50), `type` (JOINT or LINEAR, default JOINT),
`tcp_max_velocity` (above 0 up to 2 m/s, default 2) and `acceleration` (above 0 up to 200 %). Rozum's later
SDK's `motionType` and `velocity` are accepted too, and so are its waypoint `blend` and `actions`.

Beyond the reference guide, every operation of Rozum's SDK 1.8.4 (pulse-api / pdhttp) is served: the robot
state and failures, identity and versions, the tool's info and shape, the environment's obstacles, the
protective stop, free drive, jogging, gripper power, untwisting, the motors' log and the /run/* motions.

Access: a pendant exposed beyond loopback (`pendant --host 0.0.0.0`) has an access token (printed at
start-up, or `--token`). Every request that changes the robot (any method but GET, HEAD and OPTIONS) must
then carry it in the `X-Pendant-Token` header: without it the answer is 401, with a wrong one 403 (429 after
many wrong ones). Reads and stops (`PUT /freeze`, `POST /stop`) need no token, and a stop is never refused for
its form (any content type, any body or none). A command from a web page of another origin, or one naming a
`Host` the pendant does not answer to, is refused (403); a page's command with its body sent as `text/plain`
or a form too (415). Scripts (no `Origin`, no `Sec-Fetch-*` header) may label a JSON body as they like.
While the operator has Remote control off in the pendant's page, commands answer 403 naming who has control;
while a jog is held there, 409.
"""


CONTROLLER_ROUTERS: tuple[Callable[[Controller], APIRouter], ...] = (
    position_router,
    pose_router,
    status_router,
    tool_router,
    base_router,
    robot_router,
    gripper_router,
    signal_router,
    system_router,
    cell_router,
    safety_router,
    run_router,
)


def _check_every_row_is_served(routers: list[APIRouter], *, with_sim: bool) -> None:
    """Every row of the operations table has its route (the /sim rows with the simulator), and no route is
    outside the table: an operation is a row plus its handler, never one without the other."""
    served = {
        (method, route.path_format)
        for router in routers
        for route in router.routes
        if isinstance(route, APIRoute)
        for method in route.methods or ()
    }
    rows = {(op.method, op.path) for op in OPERATIONS if with_sim or op.source is not Source.SIMULATOR}
    if served != rows:
        raise RuntimeError(f"rows without a route: {rows - served}; routes without a row: {served - rows}")


def _sim_controller_type() -> type[SimController] | None:
    try:
        from pendant.sim import SimController
    except ImportError:  # the simulator is optional for a pendant in front of a real arm
        return None
    return SimController


def create_app(
    controller: Controller,
    *,
    token: str | None = None,
    events: EventLog | None = None,
    access: AccessRules | None = None,
    stops: StopBus | None = None,
) -> FastAPI:
    """The API for one controller; the /sim routes are mounted only when it is the simulator.

    `token`: when given (the pendant is exposed on a network), every command needs it in the
    `X-Pendant-Token` header (401 without, 403 wrong); reads stay open. `events`: log of every command.
    `access`: the whole guard (Host and Origin rules, Remote control; see pendant.access.http_guard), which
    `token` and `events` are shorthands for. `stops`: told of every stop request (PUT /freeze, POST /stop)
    that passed the guard, before the controller.
    """
    # /docs and /redoc from Swagger UI and ReDoc files installed with the package: they work offline.
    app = FastAPIOffline(
        title="PULSE REST API",
        version=__version__,
        description=DESCRIPTION,
        openapi_tags=docs.TAGS,
    )
    routers = [make(controller) for make in CONTROLLER_ROUTERS]
    sim_type = _sim_controller_type()
    if sim_type is not None and isinstance(controller, sim_type):
        from pendant.api.routers.sim import sim_router

        routers.append(sim_router(controller))
    for router in routers:
        app.include_router(router)
    _check_every_row_is_served(routers, with_sim=len(routers) > len(CONTROLLER_ROUTERS))

    install_error_handlers(app)
    app.add_middleware(DirectDispatch, table=direct_endpoints(routers))
    if sim_type is not None and isinstance(controller, sim_type):
        app.add_middleware(UnavailableFirst, check_alive=controller.check_alive)
    if stops is not None:
        app.add_middleware(StopNotice, stops=stops)
    app.add_middleware(BodySizeLimit)  # before any body is read
    rules = access if access is not None else AccessRules(token=token, events=events)
    if rules.active:
        app.add_middleware(AccessGuard, rules=rules)  # added last: runs first (no body needed to refuse)
    app.openapi = lambda: _openapi(app)  # type: ignore[method-assign]  # FastAPI's documented way to extend the schema
    app.state.controller = controller
    return app


def _openapi(app: FastAPI) -> dict[str, Any]:
    """FastAPI's schema, minus its 422 (never sent: see pendant.api.errors), plus the body schemas."""
    if app.openapi_schema is not None:
        return app.openapi_schema
    schema = get_openapi(
        title=app.title,
        version=app.version,
        description=app.description,
        routes=app.routes,
        tags=app.openapi_tags,
    )
    for path, path_item in schema.get("paths", {}).items():
        for method, operation in path_item.items():
            operation.get("responses", {}).pop("422", None)
            if (method.upper(), path) in BODY_LIMITS:  # the documented body has a size limit: say so
                limit = body_limit(method.upper(), path)
                too_large = docs.error(413, "Request body too large", too_large_message(limit))
                operation["responses"].update({str(status): answer for status, answer in too_large.items()})
                operation["requestBody"]["description"] += f" (at most {limit} bytes)"
    components = schema.setdefault("components", {}).setdefault("schemas", {})
    for unused in ("HTTPValidationError", "ValidationError"):
        components.pop(unused, None)
    for op in OPERATIONS:  # the request bodies' models, as the operations table names them
        if op.schema is not None:
            _add_body_schema(components, op.schema.removesuffix("[]"), op.request)
    components["Tool"]["properties"]["radius"]["minimum"] = 0
    app.openapi_schema = schema
    return schema


_REF = "#/components/schemas/{model}"


def _add_body_schema(components: dict[str, Any], name: str, request: Any) -> None:
    if get_origin(request) is list:
        request = get_args(request)[0]
    body_schema = TypeAdapter(request).json_schema(ref_template=_REF)
    for defined, definition in body_schema.pop("$defs", {}).items():
        components.setdefault(defined, definition)
    components.setdefault(name, body_schema)
