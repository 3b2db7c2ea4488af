"""SDK 1.8.4: the protective stop and its input bindings, free drive, jogging, untwisting."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.concurrency import run_in_threadpool
from pydantic import TypeAdapter

from pendant.api import docs
from pendant.api.errors import MSG_INPUT_PORT
from pendant.api.params import InputPort, json_body, read_body
from pendant.api.wire import TextResponse, string_result
from pendant.controller.errors import MSG_JOG_BLOCKED, MSG_PROTECTIVE_STOP
from pendant.controller.protocol import Controller
from pendant.controller.system_types import JoggingAcceleration
from pendant.controller.types import SignalLevel

JOGGING = TypeAdapter(JoggingAcceleration)
EXAMPLE_JOG = {"acceleration": {"x": 0.5, "y": 0.0, "z": 0.0, "rx": 0.0, "ry": 0.0, "rz": 0.0}}


def safety_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=[docs.TAG_SAFETY])

    @router.post(
        "/stop",
        summary="Protective stop",
        description=(
            "The arm stops where it is and holds; motion commands answer 412 until PUT /recover. Recorded "
            "in GET /status/failure (STOP_2)."
        ),
        response_class=TextResponse,
        responses={**docs.text_result("Stopped", MSG_PROTECTIVE_STOP), **docs.arm_errors()},
    )
    async def stop() -> TextResponse:
        return string_result(controller.stop())

    def bind(port: int, level: SignalLevel) -> TextResponse:
        return string_result(controller.bind_stop(port, level))

    bind_responses = {
        **docs.text_result("Bound", "Stop bound to digital input 1 going HIGH"),
        **docs.precondition(MSG_INPUT_PORT),
        **docs.arm_errors(),
    }

    @router.put(
        "/stop/bind/{port}/high",
        summary="Protective stop when a digital input goes HIGH",
        description="From now on, digital input `port` (1 to 4) changing to HIGH makes a protective stop.",
        response_class=TextResponse,
        responses=bind_responses,
    )
    async def bind_high(port: InputPort) -> TextResponse:
        return bind(port, SignalLevel.HIGH)

    @router.put(
        "/stop/bind/{port}/low",
        summary="Protective stop when a digital input goes LOW",
        description="From now on, digital input `port` (1 to 4) changing to LOW makes a protective stop.",
        response_class=TextResponse,
        responses=bind_responses,
    )
    async def bind_low(port: InputPort) -> TextResponse:
        return bind(port, SignalLevel.LOW)

    @router.delete(
        "/stop",
        summary="Unbinding the protective stop from the inputs",
        response_class=TextResponse,
        responses={**docs.text_result("Unbound", "Stop unbound from the inputs"), **docs.arm_errors()},
    )
    async def unbind() -> TextResponse:
        return string_result(controller.unbind_stop())

    @router.put(
        "/zg/on",
        summary="Free drive on",
        description="Zero gravity: the arm stops, drops its queue and can be moved by hand.",
        response_class=TextResponse,
        responses={
            **docs.text_result("Done", "Zero gravity on: the arm can be moved by hand"),
            **docs.precondition(MSG_PROTECTIVE_STOP),
            **docs.arm_errors(),
        },
    )
    async def zg_on() -> TextResponse:
        return string_result(controller.zg_on())

    @router.put(
        "/zg/off",
        summary="Free drive off",
        description="The motors hold the arm where the hand left it.",
        response_class=TextResponse,
        responses={**docs.text_result("Done", "Zero gravity off"), **docs.arm_errors()},
    )
    async def zg_off() -> TextResponse:
        return string_result(controller.zg_off())

    @router.put(
        "/jogging",
        summary="Jogging by an acceleration vector",
        description=(
            "x, y, z, rx, ry, rz in [-1, 1], in the base frame: the TCP moves that way (1 = 250 mm/s, "
            "0.5 rad/s), state JOGGING, until an all-zero vector, PUT /freeze, POST /stop, a joint limit, "
            "the workspace edge or an obstacle. A new vector while jogging changes the direction."
        ),
        response_class=TextResponse,
        responses={
            **docs.text_result("Done", "Jogging", "Jogging stopped"),
            **docs.bad_format(),
            **docs.precondition(MSG_JOG_BLOCKED, MSG_PROTECTIVE_STOP),
            **docs.arm_errors(),
        },
        openapi_extra=json_body(docs.ref("JoggingAcceleration"), EXAMPLE_JOG, "Direction and strength"),
    )
    async def jogging(request: Request) -> TextResponse:
        body = await read_body(request, JOGGING)
        return string_result(await run_in_threadpool(controller.jog, body.acceleration))

    @router.put(
        "/untwisting/finish",
        tags=[docs.TAG_SYSTEM],
        summary="Leaving the TWISTED state",
        response_class=TextResponse,
        responses={
            **docs.text_result(
                "The outcome",
                "Untwisting finished: the arm is ready",
                "The arm is not twisted: nothing to finish",
            ),
            **docs.arm_errors(),
        },
    )
    async def finish_untwisting() -> TextResponse:
        return string_result(controller.finish_untwisting())

    return router
