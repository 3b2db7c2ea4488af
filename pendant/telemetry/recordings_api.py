"""Recordings from scripts: `POST /pendant/recordings` starts one (optionally named), `POST
/pendant/recordings/{name}/stop` finishes it, `GET /pendant/recordings` lists them. The same Telemetry as
the Dashboard's Recording section: the same files, in the same folder, shown there too."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from fastapi import APIRouter, Request
from pydantic import BaseModel, ConfigDict, ValidationError
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

from pendant.eventlog import EventKind, EventLog
from pendant.telemetry.recordings import RecordingError, RecordingRefused, name_of
from pendant.telemetry.sampler import Telemetry

RECORDINGS_PATH = "/pendant/recordings"
WHO = "api"


class StartRecording(BaseModel):
    """The optional body of POST /pendant/recordings."""

    model_config = ConfigDict(extra="forbid")

    name: str | None = None


@dataclass
class RecordingDesk:
    """Where the API finds the pendant's Telemetry: the page's, once it has started, or the headless one."""

    telemetry: Telemetry | None = None
    events: EventLog | None = None


def _answer(status: int, body: object) -> Response:
    return Response(json.dumps(body), status_code=status, media_type="application/json")


def _files(telemetry: Telemetry, name: str) -> dict[str, Any]:
    recording = next((r for r in telemetry.recordings() if name_of(r.stem) == name), None)
    files = [path.name for path in recording.files] if recording is not None else []
    return {"name": name, "folder": str(telemetry.recordings_folder), "files": files}


def recordings_router(desk: RecordingDesk) -> APIRouter:
    router = APIRouter(tags=["pendant"])

    def telemetry() -> Telemetry:
        if desk.telemetry is None:
            raise RecordingRefused(503, "Recordings are not available yet: the pendant is still starting")
        return desk.telemetry

    def logged(message: str) -> None:
        if desk.events is not None:
            desk.events.record(EventKind.COMMAND, WHO, message)

    def refused(call: Callable[[], Response]) -> Response:
        try:
            return call()
        except RecordingRefused as error:
            return _answer(error.status, str(error))
        except RecordingError as error:  # the folder cannot hold it: the message says what to do
            return _answer(500, str(error))

    def start(name: str | None) -> Response:
        started = telemetry().start_recording(name, exclusive=True)
        logged(f"Recording {started!r} started")
        return _answer(201, {**_files(telemetry(), started), "running": True})

    def stop(name: str) -> Response:
        running = telemetry().running
        if running is None:
            raise RecordingRefused(409, f"No recording is running: {name!r} is not being recorded")
        if running != name:
            raise RecordingRefused(409, f"Recording {name!r} is not running (running: {running!r})")
        samples = telemetry().stop_recording()
        logged(f"Recording {name!r} stopped: {samples} samples")
        return _answer(200, {**_files(telemetry(), name), "running": False, "samples": samples})

    def listing() -> Response:
        found = telemetry()
        running = found.running
        return _answer(
            200,
            [
                {
                    "name": name_of(r.stem),
                    "files": [p.name for p in r.files],
                    "running": name_of(r.stem) == running,
                }
                for r in found.recordings()
            ],
        )

    @router.get(RECORDINGS_PATH, summary="The recordings kept, newest first (the Dashboard's list)")
    def get_recordings() -> Response:
        return refused(listing)

    @router.post(
        RECORDINGS_PATH,
        summary="Start a recording (MCAP and CSV, as the Dashboard's Record button)",
        description='Body (optional): `{"name": "pick-test"}`, 1 to 64 letters, digits, `-`, `_` or `.`; '
        "without it the recording is named by its start time. Answers 201 with its name and files; 400 for "
        "a bad name or body, 409 when a recording is running or the name is taken.",
        status_code=201,
        responses={400: {"description": "A bad name or body"}, 409: {"description": "Running, or taken"}},
        openapi_extra={
            "requestBody": {
                "required": False,
                "content": {"application/json": {"schema": StartRecording.model_json_schema()}},
            }
        },
    )
    async def post_recording(request: Request) -> Response:
        body = await request.body()
        try:
            options = StartRecording.model_validate(json.loads(body) if body.strip() else {})
        except (ValueError, ValidationError) as error:
            reason = error.errors()[0]["msg"] if isinstance(error, ValidationError) else str(error)
            return _answer(400, f'Bad body: {reason}; expected nothing or {{"name": "..."}}')
        return await run_in_threadpool(refused, lambda: start(options.name))

    @router.post(
        RECORDINGS_PATH + "/{name}/stop",
        summary="Stop the running recording `name` and finish its files",
        responses={409: {"description": "No recording of that name is running"}},
    )
    async def stop_recording(name: str) -> Response:
        return await run_in_threadpool(refused, lambda: stop(name))

    return router
