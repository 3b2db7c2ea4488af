"""`POST /pendant/preflight`: the pre-flight over the pendant's API (the same check as `pendant preflight`).

The body is a program document (as saved), or {"program": {...}, "cell": {...} | null, "inputs": {"1":
"HIGH"}, "while_loop_passes": 1}. The twin is seeded from the controller the pendant drives, with GET
requests only: a real arm behind the proxy does not move and is sent nothing else. 200 with the report
(its "ok" says whether every step passes); 400 with the reason when the program, the cell or the options
are refused; 409 while another pre-flight runs (one at a time: each takes a core for up to a second).
"""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, Request, Response
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from starlette.concurrency import run_in_threadpool

from pendant.cell.file import Cell
from pendant.controller import Controller, ControllerError
from pendant.controller.types import SignalLevel
from pendant.planning.preflight import MAX_LOOP_PASSES, PreflightRefused, preflight
from pendant.planning.twin import read_seed
from pendant.program.files import ProgramFileError, ProgramStore, parse_program

PREFLIGHT_PATH = "/pendant/preflight"
MSG_BUSY = "A pre-flight is running: try again when it has finished"


class PreflightOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")

    program: dict[str, object]
    cell: Cell | None = None
    inputs: dict[Annotated[int, Field(ge=1, le=4)], SignalLevel] = {}
    while_loop_passes: Annotated[int, Field(ge=0, le=MAX_LOOP_PASSES)] = 1


_BODY_DOC: dict[str, object] = {
    "description": 'A program document as saved, or {"program": ..., "cell": ..., "inputs": {"1": "HIGH"}, '
    '"while_loop_passes": 1}',
    "required": True,
    "content": {"application/json": {"schema": {"type": "object"}}},
}


def _refusal(status: int, message: str) -> Response:
    return Response(json.dumps(message), status_code=status, media_type="text/plain")


def _options(body: bytes) -> PreflightOptions:
    try:
        document = json.loads(body)
    except ValueError as error:
        raise PreflightRefused(f"the body is not JSON: {error}") from None
    if not isinstance(document, dict):
        raise PreflightRefused('the body must be a program document or {"program": ...}')
    wrapped = "program" in document and "steps" not in document
    try:
        return PreflightOptions.model_validate(document if wrapped else {"program": document})
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(part) for part in first["loc"])
        raise PreflightRefused(f"{where}: {first['msg']}") from None


def preflight_router(controller: Controller, model: str, programs_dir: Path) -> APIRouter:
    """POST /pendant/preflight on `controller` (an arm of `model`); Call steps open from `programs_dir`."""
    router = APIRouter(tags=["pendant"])
    one_at_a_time = threading.Lock()

    # Run in the thread pool (the body is read first, on the event loop): a check never blocks the loop.
    def run_preflight(body: bytes) -> Response:
        try:
            options = _options(body)
            program = parse_program(json.dumps(options.program).encode(), "the request's program")
        except (PreflightRefused, ProgramFileError) as error:
            return _refusal(400, str(error))
        if not one_at_a_time.acquire(blocking=False):
            return _refusal(409, MSG_BUSY)
        try:
            seed = read_seed(controller)
            if options.cell is not None:
                seed = seed.with_cell(options.cell.obstacles, options.cell.tool_shape)
            report = preflight(
                program,
                seed,
                model=model,
                load=ProgramStore(programs_dir).load,
                inputs=options.inputs,
                loop_passes=options.while_loop_passes,
            )
        except PreflightRefused as error:
            return _refusal(400, str(error))
        except ControllerError as error:
            return _refusal(error.status_code, f"Cannot read the arm: {error.message}")
        finally:
            one_at_a_time.release()
        return Response(json.dumps(report.as_json()), media_type="application/json")

    @router.post(
        PREFLIGHT_PATH,
        summary="Check a program on the digital twin (nothing moves)",
        openapi_extra={"requestBody": _BODY_DOC},
    )
    async def post_preflight(request: Request) -> Response:
        return await run_in_threadpool(run_preflight, await request.body())

    return router
