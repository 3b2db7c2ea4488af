"""Request parameters and bodies: parsed here, so the routers get typed values or the right error.

Bodies are read and validated by the API itself (pydantic-core's JSON parser against the contract's strict
models) rather than by FastAPI, for three reasons: every failure must become 400 "Incorrect format of input
Message" (never 422); NaN and Infinity literals must be refused (the models only accept finite numbers, and
integers are accepted where a double is expected, as JSON clients send `0`); and the Content-Type is not
required to be `application/json` (`curl -d` sends form encoding; the controller reads JSON regardless).

A body's size is bounded before it gets here (pendant.api.limits); one larger than a single document (a run
of waypoints) is parsed in a worker thread, so the event loop stays free for PUT /freeze meanwhile.
"""

from __future__ import annotations

from typing import Annotated, Any, TypeVar

from fastapi import Path, Query, Request
from fastapi.concurrency import run_in_threadpool
from pydantic import TypeAdapter, ValidationError

from pendant.controller.errors import BadRequest
from pendant.controller.types import (
    ACCELERATION_MAX,
    DEFAULT_GRIPPER_TIMEOUT_MS,
    DEFAULT_SPEED_PERCENT,
    GRIPPER_TIMEOUT_MAX_MS,
    INPUT_PORTS,
    OUTPUT_PORTS,
    SPEED_MAX,
    SPEED_MIN,
    TCP_MAX_VELOCITY_MAX,
    TCP_MAX_VELOCITY_MIN,
    MotionParams,
    MotionType,
)

T = TypeVar("T")

# Parsing up to this many bytes takes a few microseconds: cheaper on the loop than a hop to a thread.
INLINE_PARSE_MAX_BYTES = 4096

# The bodies' parsers are the operations table's models (pendant.api.operation_route.body_of).


async def read_body(request: Request, adapter: TypeAdapter[T]) -> T:
    """The request body as `adapter`'s type, or BadRequest (400) whatever is wrong with it."""
    body = await request.body()
    try:
        if len(body) <= INLINE_PARSE_MAX_BYTES:
            return adapter.validate_json(body)
        return await run_in_threadpool(adapter.validate_json, body)
    except (ValidationError, ValueError) as exc:
        raise BadRequest() from exc


# --- query parameters of the motion commands -------------------------------------------------------------

# Bounds as Rozum's SDK checks them: above 0 (exclusive), at most 100 % (acceleration 200 %).
_PERCENT = {"gt": SPEED_MIN, "le": SPEED_MAX, "allow_inf_nan": False}

# Optional parameters are typed without `| None` so the schema says "number", not "number or null" (a query
# string has no null); FastAPI uses the None default as is when the parameter is absent.
SpeedQuery = Annotated[
    float,
    Query(
        **_PERCENT,
        description=(
            f"Speed in percent of the maximum speed, above {SPEED_MIN:g} up to {SPEED_MAX:g}. Optional: "
            f"without it (and without `velocity`) the arm moves at {DEFAULT_SPEED_PERCENT:g} %, capped by "
            "`tcp_max_velocity` (Rozum's SDK examples send only that)."
        ),
        examples=[50],
    ),
]
TypeQuery = Annotated[
    MotionType,
    Query(
        alias="type",
        description=(
            "Motion type: JOINT (a curve in joint space, the fastest) or LINEAR (a straight TCP line). "
            "Default JOINT."
        ),
    ),
]
MotionTypeQuery = Annotated[
    MotionType,
    Query(alias="motionType", description="Alias of `type`, as Rozum's later SDK sends it."),
]
TcpMaxVelocityQuery = Annotated[
    float,
    Query(
        gt=TCP_MAX_VELOCITY_MIN,
        le=TCP_MAX_VELOCITY_MAX,
        allow_inf_nan=False,
        description=(
            f"Limit of the TCP velocity in m/s, above {TCP_MAX_VELOCITY_MIN:g} up to "
            f"{TCP_MAX_VELOCITY_MAX:g}. "
            f"Default {TCP_MAX_VELOCITY_MAX:g}."
        ),
    ),
]
VelocityQuery = Annotated[
    float,
    Query(
        **_PERCENT,
        description=(
            f"Rozum's later SDK: velocity in percent (above {SPEED_MIN:g} up to {SPEED_MAX:g}), in place of "
            "`speed` (with `acceleration`)."
        ),
    ),
]
AccelerationQuery = Annotated[
    float,
    Query(
        gt=SPEED_MIN,
        le=ACCELERATION_MAX,
        allow_inf_nan=False,
        description=(
            f"Acceleration in percent of the joints' limits (above {SPEED_MIN:g} up to "
            f"{ACCELERATION_MAX:g}); default: the speed's percentage."
        ),
    ),
]


# `None` is "not sent": the annotations stay plain so the OpenAPI schema shows no null (hence the ignores).
async def motion_params(
    speed: SpeedQuery = None,  # type: ignore[assignment]  # None: not sent
    motion_type: TypeQuery = None,  # type: ignore[assignment]  # None: not sent
    motion_type_sdk: MotionTypeQuery = None,  # type: ignore[assignment]  # None: not sent
    tcp_max_velocity: TcpMaxVelocityQuery = TCP_MAX_VELOCITY_MAX,
    velocity: VelocityQuery = None,  # type: ignore[assignment]  # None: not sent
    acceleration: AccelerationQuery = None,  # type: ignore[assignment]  # None: not sent
) -> MotionParams:
    """The motion parameters of PUT /position, /pose, /positions/run, /poses/run.

    `speed` wins over `velocity` when both are given; `type` wins over `motionType`.
    """
    chosen_speed = speed if speed is not None else velocity
    if chosen_speed is None:
        chosen_speed = DEFAULT_SPEED_PERCENT
    return MotionParams(
        speed=chosen_speed,
        motion_type=motion_type or motion_type_sdk or MotionType.JOINT,
        tcp_max_velocity=tcp_max_velocity,
        acceleration=acceleration,
    )


TimeoutQuery = Annotated[
    float,
    Query(
        ge=0,
        le=GRIPPER_TIMEOUT_MAX_MS,
        allow_inf_nan=False,
        description=(
            f"How long (ms, fractions allowed) the arm waits for the gripper, 0 to {GRIPPER_TIMEOUT_MAX_MS}, "
            f"default "
            f"{DEFAULT_GRIPPER_TIMEOUT_MS}. Values above 0 are recommended."
        ),
    ),
]

OutputPort = Annotated[
    int,
    Path(
        ge=OUTPUT_PORTS[0],
        le=OUTPUT_PORTS[-1],
        description="Digital output (relay) on the control box: 1 or 2.",
    ),
]
InputPort = Annotated[
    int,
    Path(
        ge=INPUT_PORTS[0],
        le=INPUT_PORTS[-1],
        description="Digital input on the control box: 1 to 4.",
    ),
]


def json_body(schema: dict[str, Any], example: Any, description: str) -> dict[str, Any]:
    """`openapi_extra` documenting a JSON request body that the handler parses itself."""
    return {
        "requestBody": {
            "required": True,
            "description": description,
            "content": {"application/json": {"schema": schema, "example": example}},
        }
    }
