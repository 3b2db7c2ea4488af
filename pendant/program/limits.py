"""The bounds a program's fields are checked against, and the field types that carry them: the limits a
taught program, a hand-edited file and the editor share (pendant.program.models builds the steps from them).
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, Field

from pendant.controller.types import INPUT_PORTS, MAX_RUN_WAYPOINTS, OUTPUT_PORTS, SPEED_MAX

SCHEMA_VERSION = 2
DEFAULT_SPEED_PERCENT = 20.0
DEFAULT_INPUT_TIMEOUT_MS = 5000
DEFAULT_APPROACH_MM = 50.0
DEFAULT_PALLET_NAME = "Pallet"
MAX_WAIT_MS = 3_600_000  # an hour: anything longer is a typo, not a program
WAYPOINT_NAME_MAX = 40
PROGRAM_NAME_MAX = 64
# A program is saved only if it can be loaded back: 2,000 steps of the longest kind (a move, 40-character
# name) take ~1.6 MB as saved, under the 5 MB a file may have (pendant.program.files.MAX_FILE_BYTES).
MAX_STEPS = 2000
COMMENT_MAX = 200
MAX_LOOP_TIMES = 1_000_000
MAX_GRID = 100  # rows, columns or layers of a pallet
MAX_OFFSET_MM = 2000.0  # a relative move further than the arm reaches is a typo
MAX_BLEND_MM = 500.0
MAX_NESTING = 16  # Loops in Ifs in Pallets ...: deeper is not a program a person taught
# Recorded paths: at most one controller run each; 5,000 points in all (~2.9 MB saved) keep the largest
# program under the 5 MB a file may have, beside moves filling the rest of the 2,000 steps.
MAX_PATH_POINTS = MAX_RUN_WAYPOINTS
MAX_PROGRAM_PATH_POINTS = 5_000
DEFAULT_PATH_NAME = "path"
DEFAULT_PATH_SPEED_MM_S = 100.0
PATH_SPEED_MAX_MM_S = 2000.0  # the /run/linear velocity limit (2 m/s)

WaypointName = Annotated[str, Field(min_length=1, max_length=WAYPOINT_NAME_MAX)]
# A step's speed: 0 % would be accepted here and fail only when run, so the editor refuses it with the range.
PROGRAM_SPEED_MIN = 1.0


def _speed_in_range(speed: float) -> float:
    if not PROGRAM_SPEED_MIN <= speed <= SPEED_MAX:
        raise ValueError(f"Speed must be {PROGRAM_SPEED_MIN:g} to {SPEED_MAX:g} %, not {speed:g}")
    return speed


Speed = Annotated[
    float,
    Field(allow_inf_nan=False, json_schema_extra={"minimum": PROGRAM_SPEED_MIN, "maximum": SPEED_MAX}),
    AfterValidator(_speed_in_range),
]
Millis = Annotated[int, Field(ge=0, le=MAX_WAIT_MS)]
OutputPort = Annotated[int, Field(ge=min(OUTPUT_PORTS), le=max(OUTPUT_PORTS))]
InputPort = Annotated[int, Field(ge=min(INPUT_PORTS), le=max(INPUT_PORTS))]
Millimetres = Annotated[float, Field(ge=-MAX_OFFSET_MM, le=MAX_OFFSET_MM, allow_inf_nan=False)]
Degrees = Annotated[float, Field(ge=-360.0, le=360.0, allow_inf_nan=False)]
GridCount = Annotated[int, Field(ge=1, le=MAX_GRID)]
