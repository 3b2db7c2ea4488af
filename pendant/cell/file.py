"""Cell files: the obstacles (and the tool shape) as versioned JSON, written atomically like programs, and
applied to a controller so that its checks hold exactly the saved cell."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pendant.controller import Controller, ControllerError
from pendant.controller.cell_types import MAX_OBSTACLES, Obstacle, ToolShape
from pendant.program.files import ProgramFileError, atomic_write, sanitize_name

SCHEMA_VERSION: Literal[1] = 1
SUFFIX = ".cell.json"
CELLS_DIR_ENV = "PENDANT_CELLS_DIR"
DEFAULT_CELLS_DIR = Path("cells")  # relative to the pendant's working directory
MAX_FILE_BYTES = 1_000_000  # 100 obstacles of 16 plane points are ~200 kB


class CellFileError(Exception):
    """A cell file that cannot be read, written or applied; the message says why."""


class Cell(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    schema_version: Literal[1] = SCHEMA_VERSION
    obstacles: Annotated[list[Obstacle], Field(max_length=MAX_OBSTACLES)] = []
    tool_shape: ToolShape | None = None  # None: the file leaves the controller's tool shape as it is


def cells_dir() -> Path:
    return Path(os.environ.get(CELLS_DIR_ENV, DEFAULT_CELLS_DIR))


def cell_path(folder: Path, name: str) -> Path:
    try:
        return folder / f"{sanitize_name(name)}{SUFFIX}"
    except ProgramFileError as error:
        raise CellFileError(str(error)) from None


def list_cells(folder: Path) -> list[str]:
    if not folder.is_dir():
        return []
    return sorted(p.name.removesuffix(SUFFIX) for p in folder.glob(f"*{SUFFIX}") if p.is_file())


def dump_cell(cell: Cell) -> bytes:
    return (cell.model_dump_json(indent=2) + "\n").encode()


def parse_cell(data: bytes, source: str) -> Cell:
    if len(data) > MAX_FILE_BYTES:
        raise CellFileError(f"{source}: larger than {MAX_FILE_BYTES} bytes: not a cell file")
    try:
        return Cell.model_validate_json(data)
    except ValidationError as error:
        first = error.errors()[0]
        where = ".".join(str(part) for part in first["loc"])
        raise CellFileError(f"{source}: not a cell file ({where}: {first['msg']})") from None


def save_cell(folder: Path, name: str, cell: Cell) -> Path:
    path = cell_path(folder, name)
    atomic_write(path, dump_cell(cell))
    return path


def load_cell(folder: Path, name: str) -> Cell:
    path = cell_path(folder, name)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise CellFileError(f"no cell file named {name!r}") from None
    return parse_cell(data, path.name)


def read_cell(controller: Controller, *, with_tool_shape: bool = True) -> Cell:
    shape = controller.get_tool_shape() if with_tool_shape else None
    return Cell(obstacles=controller.get_obstacles(), tool_shape=shape)


def apply_cell(controller: Controller, cell: Cell) -> None:
    """Make the controller hold exactly `cell`. If it refuses any part (an obstacle touching the arm), the
    cell it held before is put back and the refusal raised: half a cell would check the wrong thing."""
    before = read_cell(controller, with_tool_shape=cell.tool_shape is not None)
    try:
        _put(controller, cell)
    except ControllerError:
        _put(controller, before)
        raise


def _put(controller: Controller, cell: Cell) -> None:
    controller.remove_obstacles()
    if cell.tool_shape is not None:
        controller.set_tool_shape(cell.tool_shape)
    for obstacle in cell.obstacles:
        controller.add_obstacle(obstacle)
