"""The controller's cell as coal geometry in the pendant, so the page checks what the controller checks.

Built with the simulator's own shape builders: the ghost turns red exactly where the simulator refuses.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from pendant.controller import ControllerError, Point, Rotation, Tool
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.kinematics import ArmModel
from pendant.kinematics.obstacles import CellGeometry
from pendant.sim.environment import _obstacle_shape, _tool_capsules

PATH_STEP_RAD = np.radians(2.0)  # the joint path is checked every 2° of the joint that travels most


class CellModel:
    """Obstacles by name and the tool's capsules, checked against the arm at any joint angles."""

    def __init__(
        self, arm: ArmModel, obstacles: Sequence[Obstacle], shape: ToolShape, tool: Tool | None = None
    ) -> None:
        self.arm = arm
        self.obstacles = list(obstacles)
        self.shape = shape
        capsules = _tool_capsules(shape, tool if tool is not None else _NO_TOOL)
        self._each: list[tuple[str, CellGeometry]] = []
        shapes = []
        for obstacle in self.obstacles:
            try:
                built = _obstacle_shape(obstacle)
            except ControllerError:  # a plane on a line: the controller refuses it, so it never holds one
                continue
            shapes.append(built)
            self._each.append((obstacle.name, CellGeometry(arm, [built], capsules)))
        self.geometry = CellGeometry(arm, shapes, capsules)

    def collides(self, q: np.ndarray) -> bool:
        return self.geometry.collides(q)

    def touching(self, q: np.ndarray) -> list[str]:
        """The names of the obstacles the arm or its tool touches at q."""
        if not self._each:
            return []
        return [name for name, geometry in self._each if geometry.collides(q)]

    def path_touching(self, q_from: np.ndarray, q_to: np.ndarray) -> list[str]:
        """The obstacles hit along the joint-interpolated path from q_from to q_to (Move J's path)."""
        if not self._each:
            return []
        steps = max(1, int(np.ceil(float(np.max(np.abs(q_to - q_from))) / PATH_STEP_RAD)))
        hit: list[str] = []
        for fraction in np.linspace(0.0, 1.0, steps + 1):
            q = q_from + fraction * (q_to - q_from)
            if self.geometry.collides(q):
                hit.extend(name for name in self.touching(q) if name not in hit)
        return hit


_NO_TOOL = Tool(
    name="flange",
    point=Point(x=0.0, y=0.0, z=0.0),
    rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
    radius=0.0,
)


class CellAwareArm:
    """The arm model whose collision check includes the cell (obstacles, tool shape): given to the jogger, a
    jog stops short of an obstacle as it does of the floor. Everything else is the arm model's."""

    def __init__(self, arm: ArmModel, cell: Callable[[], CellModel | None]) -> None:
        self._arm = arm
        self._cell = cell

    def in_collision(self, q: np.ndarray) -> bool:
        if self._arm.in_collision(q):
            return True
        cell = self._cell()
        return cell is not None and cell.collides(q)

    def __getattr__(self, name: str) -> Any:
        return getattr(self._arm, name)
