"""SDK 1.8.4: the protective stop and its input bindings, free drive, jogging, untwisting."""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.concurrency import run_in_threadpool

from pendant.api import docs
from pendant.api.errors import MSG_INPUT_PORT
from pendant.api.operation_route import body_of, serve
from pendant.api.params import InputPort, read_body
from pendant.api.wire import TextResponse, string_result
from pendant.controller.errors import MSG_JOG_BLOCKED, MSG_PROTECTIVE_STOP
from pendant.controller.protocol import Controller
from pendant.controller.types import SignalLevel

EXAMPLE_JOG = {"acceleration": {"x": 0.5, "y": 0.0, "z": 0.0, "rx": 0.0, "ry": 0.0, "rz": 0.0}}


def safety_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=[docs.TAG_SAFETY])

    @serve(
        router,
        "POST /stop",
        summary="Protective stop",
        description=(
            "The arm stops where it is and holds; motion commands answer 412 until PUT /recover. Recorded "
            "in GET /status/failure (STOP_2)."
        ),
        ok="Stopped",
        example=[MSG_PROTECTIVE_STOP],
        errors=docs.arm_errors(),
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

    @serve(
        router,
        "PUT /stop/bind/{port}/high",
        summary="Protective stop when a digital input goes HIGH",
        description="From now on, digital input `port` (1 to 4) changing to HIGH makes a protective stop.",
        errors=bind_responses,
    )
    async def bind_high(port: InputPort) -> TextResponse:
        return bind(port, SignalLevel.HIGH)

    @serve(
        router,
        "PUT /stop/bind/{port}/low",
        summary="Protective stop when a digital input goes LOW",
        description="From now on, digital input `port` (1 to 4) changing to LOW makes a protective stop.",
        errors=bind_responses,
    )
    async def bind_low(port: InputPort) -> TextResponse:
        return bind(port, SignalLevel.LOW)

    @serve(
        router,
        "DELETE /stop",
        summary="Unbinding the protective stop from the inputs",
        ok="Unbound",
        example=["Stop unbound from the inputs"],
        errors=docs.arm_errors(),
    )
    async def unbind() -> TextResponse:
        return string_result(controller.unbind_stop())

    @serve(
        router,
        "PUT /zg/on",
        summary="Free drive on",
        description="Zero gravity: the arm stops, drops its queue and can be moved by hand.",
        ok="Done",
        example=["Zero gravity on: the arm can be moved by hand"],
        errors={**docs.precondition(MSG_PROTECTIVE_STOP), **docs.arm_errors()},
    )
    async def zg_on() -> TextResponse:
        return string_result(controller.zg_on())

    @serve(
        router,
        "PUT /zg/off",
        summary="Free drive off",
        description="The motors hold the arm where the hand left it.",
        ok="Done",
        example=["Zero gravity off"],
        errors=docs.arm_errors(),
    )
    async def zg_off() -> TextResponse:
        return string_result(controller.zg_off())

    @serve(
        router,
        "PUT /jogging",
        summary="Jogging by an acceleration vector",
        description=(
            "x, y, z, rx, ry, rz in [-1, 1], in the base frame: the TCP moves that way (1 = 250 mm/s, "
            "0.5 rad/s), state JOGGING, until an all-zero vector, PUT /freeze, POST /stop, a joint limit, "
            "the workspace edge or an obstacle. A new vector while jogging changes the direction."
        ),
        ok="Done",
        example=["Jogging", "Jogging stopped"],
        errors={
            **docs.bad_format(),
            **docs.precondition(MSG_JOG_BLOCKED, MSG_PROTECTIVE_STOP),
            **docs.arm_errors(),
        },
        body_example=EXAMPLE_JOG,
        body_description="Direction and strength",
    )
    async def jogging(request: Request) -> TextResponse:
        body = await read_body(request, body_of("PUT /jogging"))
        return string_result(await run_in_threadpool(controller.jog, body.acceleration))

    @serve(
        router,
        "PUT /untwisting/finish",
        summary="Leaving the TWISTED state",
        ok="The outcome",
        example=["Untwisting finished: the arm is ready", "The arm is not twisted: nothing to finish"],
        errors=docs.arm_errors(),
        tags=[docs.TAG_SYSTEM],
    )
    async def finish_untwisting() -> TextResponse:
        return string_result(controller.finish_untwisting())

    return router
