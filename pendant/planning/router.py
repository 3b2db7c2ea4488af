"""`POST /pendant/preflight`: the pre-flight over the pendant's API (the same check as `pendant preflight`).

The body is a program document (as saved), or {"program": {...}, "cell": {...} | null, "inputs": {"1":
"HIGH"}, "while_loop_passes": 1} (pendant.planning.preflight_body). The twin is seeded from the controller
the pendant drives, with GET requests only: a real arm behind the proxy does not move and is sent nothing
else. 200 with the report (its "ok" says whether every step passes); 400 with the reason when the program,
the cell or the options are refused; 422 when the program would take more steps or time to check than a
pre-flight may (pendant.planning.budget); 409 while another pre-flight runs (one at a time); 503 when the
pendant is quitting. The body is parsed and checked in a process of its own (pendant.planning.worker):
however large or slow, it never holds up the server, nor PUT /freeze.
"""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter, Request, Response
from starlette.concurrency import run_in_threadpool

from pendant.controller import Controller, ControllerError
from pendant.planning.twin import TwinSeed, read_seed
from pendant.planning.worker import Job, Outcome, PreflightWorker

PREFLIGHT_PATH = "/pendant/preflight"
MSG_BUSY = "A pre-flight is running: try again when it has finished"

_BODY_DOC: dict[str, object] = {
    "description": 'A program document as saved, or {"program": ..., "cell": ..., "inputs": {"1": "HIGH"}, '
    '"while_loop_passes": 1}',
    "required": True,
    "content": {"application/json": {"schema": {"type": "object"}}},
}


def preflight_router(
    controller: Controller, model: str, programs_dir: Path, worker: PreflightWorker | None = None
) -> APIRouter:
    """POST /pendant/preflight on `controller` (an arm of `model`); Call steps open from `programs_dir`.
    `worker`: the process pre-flights run in (give one to cancel it when quitting); default a new one."""
    router = APIRouter(tags=["pendant"])
    preflights = worker if worker is not None else PreflightWorker()
    job = Job(model=model, programs_dir=str(programs_dir))

    def seed() -> TwinSeed | Outcome:
        try:
            return read_seed(controller)
        except ControllerError as error:
            return Outcome.refused(error.status_code, f"Cannot read the arm: {error.message}")

    def answer(outcome: Outcome) -> Response:
        kind = "application/json" if outcome.status == 200 else "text/plain"
        return Response(outcome.body, status_code=outcome.status, media_type=kind)

    # In the thread pool (the body is read first, on the event loop), which only waits for the worker.
    def run_preflight(body: bytes) -> Response:
        return answer(preflights.run(body, job, seed))

    @router.post(
        PREFLIGHT_PATH,
        summary="Check a program on the digital twin (nothing moves)",
        openapi_extra={"requestBody": _BODY_DOC},
    )
    async def post_preflight(request: Request) -> Response:
        # The turn first, then the body: while one pre-flight runs, the next is answered 409 unread (uvicorn
        # drops the rest of it), so four clients sending 5 MB at once never have 20 MB held in the server.
        if not preflights.claim():
            return answer(Outcome.refused(409, MSG_BUSY))
        try:
            # Not cancelled midway: anyio waits for the thread before this returns, so the turn is never
            # released while the worker's pipe is still in use.
            return await run_in_threadpool(run_preflight, await request.body())
        finally:
            preflights.release()

    return router
