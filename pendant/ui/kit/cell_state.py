"""What the controller reports about its cell and its safety, read a few times a second for every browser.

Each read stands alone: an operation a controller lacks (older firmware, 404) marks that feature
unsupported, and the page greys it out with that message instead of failing.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TypeVar

from pendant.controller import Controller, ControllerError
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.errors import Unsupported
from pendant.controller.system_types import Failure, SystemState

T = TypeVar("T")


@dataclass(frozen=True)
class CellState:
    obstacles: tuple[Obstacle, ...] = ()
    tool_shape: ToolShape = field(default_factory=lambda: ToolShape(shape=[]))
    system_state: SystemState | None = None
    failures: tuple[Failure, ...] = ()
    # feature -> the controller's message, for each feature it lacks ("environment", "status", ...)
    unsupported: dict[str, str] = field(default_factory=dict)
    # the obstacles touching the arm where it stands, with the links touching each (the pendant computes it)
    arm_contacts: tuple[tuple[str, tuple[str, ...]], ...] = ()


def _read(read: Callable[[], T], feature: str, unsupported: dict[str, str]) -> T | None:
    try:
        return read()
    except Unsupported as error:
        unsupported[feature] = error.message
    except ControllerError:
        pass
    return None


def read_cell_state(controller: Controller, previous: CellState) -> CellState:
    """One reading; what could not be read this time (a busy or offline controller) stays as it was."""
    unsupported: dict[str, str] = {}
    obstacles = _read(controller.get_obstacles, "environment", unsupported)
    shape = _read(controller.get_tool_shape, "tool shape", unsupported)
    state = _read(controller.get_system_state, "status", unsupported)
    failures = _read(controller.get_failures, "failures", unsupported)
    return CellState(
        obstacles=tuple(obstacles) if obstacles is not None else previous.obstacles,
        tool_shape=shape if shape is not None else previous.tool_shape,
        system_state=state if state is not None else previous.system_state,
        failures=tuple(failures) if failures is not None else previous.failures,
        unsupported=unsupported,
    )
