"""In simulator mode the cell outlives the pendant, as programs do: the obstacles, tool shape, tool and base
are kept in `<data>/sim-cell.json` (written atomically whenever they change, and once more on the way out)
and put back into the simulator on the next start. A file that cannot be read or applied is moved aside
(`sim-cell.json.damaged-<time>`, bytes unchanged) with a message: the pendant starts with an empty cell,
never a crash. A real arm keeps its own cell: nothing here runs with --robot."""

from __future__ import annotations

import datetime as dt
import logging
import threading
from pathlib import Path
from typing import Annotated, Literal, NamedTuple

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from pendant.cell.file import Cell, apply_cell
from pendant.controller import Controller, ControllerError
from pendant.controller.cell_types import MAX_OBSTACLES, Obstacle, ToolShape
from pendant.controller.types import Position, Tool
from pendant.program.files import atomic_write

log = logging.getLogger(__name__)

CELL_FILE = "sim-cell.json"
SAVE_PERIOD_S = 0.5  # a change is on disk within this (a kill -9 loses at most that much)
MAX_FILE_BYTES = 1_000_000


class KeptCell(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    schema_version: Literal[1] = 1
    obstacles: Annotated[list[Obstacle], Field(max_length=MAX_OBSTACLES)] = []
    tool_shape: ToolShape | None = None
    tool: Tool | None = None
    base: Position | None = None


def read_kept(controller: Controller) -> KeptCell:
    return KeptCell(
        obstacles=controller.get_obstacles(),
        tool_shape=controller.get_tool_shape(),
        tool=controller.get_tool(),
        base=controller.get_base(),
    )


def _set_aside(path: Path, why: str) -> str:
    aside = path.with_name(f"{path.name}.damaged-{dt.datetime.now():%Y%m%d-%H%M%S}")
    try:
        path.replace(aside)
    except OSError as error:
        return (
            f"The kept cell {path} {why}, and could not be moved aside ({error}): starting with an empty cell"
        )
    return f"The kept cell {path} {why}: moved aside to {aside.name}; starting with an empty cell"


class Restored(NamedTuple):
    message: str
    trouble: bool  # the kept cell could not be used: said as an error in the event log too


def restore_cell(controller: Controller, path: Path) -> Restored | None:
    """Put the kept cell back into `controller`; what to say, if anything."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        return None
    except OSError as error:
        why = error.strerror or str(error)
        return Restored(f"The kept cell {path} cannot be read ({why}): starting with an empty cell", True)
    try:
        if len(data) > MAX_FILE_BYTES:
            raise ValueError(f"larger than {MAX_FILE_BYTES} bytes")
        kept = KeptCell.model_validate_json(data)
    except (ValidationError, ValueError) as error:
        reason = error.errors()[0]["msg"] if isinstance(error, ValidationError) else str(error)
        return Restored(_set_aside(path, f"is not a cell file ({reason})"), True)
    try:
        if kept.base is not None:
            controller.set_base(kept.base)
        if kept.tool is not None:
            controller.set_tool(kept.tool)
        apply_cell(controller, Cell(obstacles=kept.obstacles, tool_shape=kept.tool_shape))
    except ControllerError as error:
        return Restored(_set_aside(path, f"was refused by the simulator ({error.message})"), True)
    return Restored(f"Cell restored from {path}: {len(kept.obstacles)} obstacle(s)", False)


class CellKeeper:
    """Writes the simulator's cell to `path` whenever it changes (read every SAVE_PERIOD_S)."""

    def __init__(self, controller: Controller, path: Path) -> None:
        self._controller = controller
        self.path = path
        self._last: KeptCell | None = self._read()  # what was restored (or fresh): nothing to write yet
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._loop, name="pendant-cell-keeper", daemon=True)
        self._warned = False

    def start(self) -> CellKeeper:
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=2.0)
        self.save()

    def _read(self) -> KeptCell | None:
        try:
            return read_kept(self._controller)
        except ControllerError:  # a fault: the cell is read again at the next turn
            return None

    def save(self) -> None:
        cell = self._read()
        if cell is None or cell == self._last:
            return
        try:
            atomic_write(self.path, (cell.model_dump_json(indent=2) + "\n").encode())
        except OSError as error:
            if not self._warned:
                log.warning("the cell cannot be kept in %s: %s", self.path, error)
                self._warned = True
            return
        self._last = cell

    def _loop(self) -> None:
        while not self._stop.wait(SAVE_PERIOD_S):
            self.save()


def keep_cell(controller: Controller, data_dir: Path, *, fresh: bool) -> tuple[CellKeeper, Restored | None]:
    """Restore the kept cell (unless `fresh`) and keep it from now on; what to say, if anything."""
    path = data_dir / CELL_FILE
    restored = None if fresh else restore_cell(controller, path)
    return CellKeeper(controller, path).start(), restored
