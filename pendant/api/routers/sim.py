"""Simulator-only controls under /sim: play the outside world (inputs, a hand on the arm, faults)."""

from __future__ import annotations

from enum import StrEnum
from typing import TYPE_CHECKING, Annotated

from fastapi import APIRouter, Path, Request
from fastapi.responses import JSONResponse

from pendant.api import docs
from pendant.api.errors import MSG_FAULT, MSG_INPUT_PORT
from pendant.api.operation_route import body_of, serve
from pendant.api.params import InputPort, read_body
from pendant.api.wire import TextResponse, empty_result
from pendant.controller.errors import MSG_COLLISION, MSG_UNREACHABLE_POSE
from pendant.controller.types import SignalLevel
from pendant.sim.fault_kinds import FAULT_KINDS, FAULT_KINDS_BY_NAME, fault_kinds_description
from pendant.sim.sim_controls import MSG_HAND_INTO_CELL, MSG_HAND_NEEDS_RELAX

if TYPE_CHECKING:
    from pendant.sim import SimController


# The faults the simulator can play, as they appear in the path: the fault kinds table's names.
FaultName = StrEnum("FaultName", [(kind.name, kind.name) for kind in FAULT_KINDS])  # type: ignore[misc]  # mypy reads only literal members

FaultPath = Annotated[FaultName, Path(description=fault_kinds_description())]


def sim_router(sim: SimController) -> APIRouter:
    router = APIRouter(prefix="/sim", tags=[docs.TAG_SIM])

    def set_input(port: int, level: SignalLevel) -> TextResponse:
        sim.set_input(port, level)
        return empty_result()

    input_responses = docs.precondition(MSG_INPUT_PORT)

    @serve(
        router,
        "PUT /sim/signal/input/{port}/high",
        summary="Simulator: set a digital input HIGH",
        errors=input_responses,
    )
    async def set_input_high(port: InputPort) -> TextResponse:
        return set_input(port, SignalLevel.HIGH)

    @serve(
        router,
        "PUT /sim/signal/input/{port}/low",
        summary="Simulator: set a digital input LOW",
        errors=input_responses,
    )
    async def set_input_low(port: InputPort) -> TextResponse:
        return set_input(port, SignalLevel.LOW)

    @serve(
        router,
        "PUT /sim/pose",
        summary="Simulator: move the relaxed arm by hand",
        description=(
            "Puts the arm at a pose (six angles in degrees) at once, as a hand would; only while the arm is "
            "relaxed (ZERO_GRAVITY, after PUT /relax), else 412; a pose beyond the joint limits, touching "
            "the arm itself or the floor, or putting the arm or its tool into an obstacle (one it did not "
            "touch, or deeper into one it touches) is refused (412) and the arm stays where it was."
        ),
        errors={
            **docs.bad_format(),
            **docs.precondition(
                MSG_HAND_NEEDS_RELAX,
                MSG_UNREACHABLE_POSE,
                MSG_COLLISION,
                MSG_HAND_INTO_CELL.format(what="'wall'"),
            ),
            **docs.arm_errors(),
        },
        body_example=docs.EXAMPLE_POSE,
        body_description="Where the hand puts the arm",
    )
    async def move_by_hand(request: Request) -> TextResponse:
        pose = await read_body(request, body_of("PUT /sim/pose"))
        sim.move_by_hand(pose)
        return empty_result()

    @serve(
        router,
        "PUT /sim/fault/{fault}",
        summary="Simulator: inject a fault",
        errors=docs.precondition(MSG_FAULT),
    )
    async def inject_fault(fault: FaultPath) -> TextResponse:
        kind = FAULT_KINDS_BY_NAME[fault.value]
        if kind.fault is None:
            sim.overheat()
        else:
            sim.inject_fault(kind.fault)
        return empty_result()

    @serve(
        router,
        "GET /sim/clock",
        summary="Simulator: its clock",
        description=(
            "The simulated time in seconds (`time`), how many times faster than the wall clock it runs "
            "(`scale`, `pendant --time-scale`), and the Unix time of that instant (`timestamp`). Every "
            "motion, gripper wait and servo temperature follows this clock."
        ),
        ok="The simulator's clock",
        example={"time": 12.5, "scale": 1.0, "timestamp": 1795000000.0},
        response_class=JSONResponse,
    )
    async def get_clock() -> JSONResponse:
        clock = sim.clock
        now = clock.now()
        return JSONResponse(
            {"time": now, "scale": getattr(clock, "scale", 1.0), "timestamp": clock.unix_time(now)}
        )

    @serve(
        router,
        "PUT /sim/reset",
        summary="Simulator: reset",
        description=(
            "Back to the start: home pose, IDLE, no fault, default tool and base, outputs and inputs LOW, no "
            "obstacle. With keep_cell=true only the fault goes: the arm stays where it stopped, with its "
            "obstacles, tool shape, tool, base and IO (a real arm's emergency stop released and recovered)."
        ),
    )
    async def reset(keep_cell: bool = False) -> TextResponse:
        sim.reset(keep_cell=keep_cell)
        return empty_result()

    return router
