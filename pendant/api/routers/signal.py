"""Digital IO on the control box: GET /signal/output/{port}, /signal/input/{port}; PUT .../high, .../low."""

from __future__ import annotations

from fastapi import APIRouter

from pendant.api import docs
from pendant.api.errors import MSG_INPUT_PORT, MSG_OUTPUT_PORT
from pendant.api.operation_route import serve
from pendant.api.params import InputPort, OutputPort
from pendant.api.wire import TextResponse, empty_result, string_result
from pendant.controller.protocol import Controller
from pendant.controller.types import SignalLevel


def signal_router(controller: Controller) -> APIRouter:
    router = APIRouter(tags=["Signals"])

    @serve(
        router,
        "GET /signal/output/{port}",
        summary="Getting the signal level on a digital output",
        description="LOW: the default state (e.g. LED off); HIGH: the changed state (e.g. LED on).",
        ok="Signal level",
        errors={**docs.precondition(MSG_OUTPUT_PORT), **docs.arm_errors()},
    )
    async def get_output(port: OutputPort) -> TextResponse:
        return string_result(controller.get_output(port).value)

    @serve(
        router,
        "GET /signal/input/{port}",
        summary="Getting the signal level on a digital input",
        description="LOW: the default state; HIGH: the changed state.",
        ok="Signal level",
        errors={**docs.precondition(MSG_INPUT_PORT), **docs.arm_errors()},
    )
    async def get_input(port: InputPort) -> TextResponse:
        return string_result(controller.get_input(port).value)

    output_responses = {**docs.precondition(MSG_OUTPUT_PORT), **docs.arm_errors()}

    @serve(
        router,
        "PUT /signal/output/{port}/high",
        summary="Setting high signal level on a digital output",
        errors=output_responses,
    )
    async def set_output_high(port: OutputPort) -> TextResponse:
        controller.set_output(port, SignalLevel.HIGH)
        return empty_result()

    @serve(
        router,
        "PUT /signal/output/{port}/low",
        summary="Setting low signal level on a digital output",
        errors=output_responses,
    )
    async def set_output_low(port: OutputPort) -> TextResponse:
        controller.set_output(port, SignalLevel.LOW)
        return empty_result()

    return router
