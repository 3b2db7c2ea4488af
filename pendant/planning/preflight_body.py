"""The body of `POST /pendant/preflight`: a program document as saved, or {"program": {...}, "cell": {...} |
null, "inputs": {"1": "HIGH"}, "while_loop_passes": 1}, checked into what `preflight` takes."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pendant.api.json_body import load_json
from pendant.cell.file import Cell
from pendant.controller.types import SignalLevel
from pendant.planning.preflight import MAX_LOOP_PASSES, PreflightRefused
from pendant.program.files import ProgramFileError, parse_program
from pendant.program.models import Program


class PreflightOptions(BaseModel):
    model_config = ConfigDict(extra="forbid")

    program: dict[str, object]
    cell: Cell | None = None
    inputs: dict[Annotated[int, Field(ge=1, le=4)], SignalLevel] = {}
    while_loop_passes: Annotated[int, Field(ge=0, le=MAX_LOOP_PASSES)] = 1


@dataclass(frozen=True)
class PreflightRequest:
    """A checked body: the program and the options to check it with."""

    program: Program
    options: PreflightOptions


def parse_request(body: bytes) -> PreflightRequest:
    """The request in `body`, or PreflightRefused saying what is wrong (depth checked before parsing)."""
    try:
        document = load_json(body)
    except ValueError as error:
        raise PreflightRefused(str(error)) from None
    if not isinstance(document, dict):
        raise PreflightRefused('the body must be a program document or {"program": ...}')
    wrapped = "program" in document and "steps" not in document
    try:
        options = PreflightOptions.model_validate(document if wrapped else {"program": document})
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(part) for part in first["loc"])
        raise PreflightRefused(f"{where}: {first['msg']}") from None
    try:
        program = parse_program(json.dumps(options.program).encode(), "the request's program")
    except ProgramFileError as error:
        raise PreflightRefused(str(error)) from None
    return PreflightRequest(program, options)
