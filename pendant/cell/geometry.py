"""The controller's cell in the pendant, so the page checks what the controller checks.

Built with the simulator's own shape builders and checker: the ghost turns red exactly where the simulator
refuses.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from pendant.controller import ControllerError, Point, Rotation, Tool
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck, NamedShape, joint_samples
from pendant.kinematics.cell_shapes import obstacle_shape, tool_capsules
from pendant.kinematics.contact import ContactGuard, Contacts, Worse

PATH_STEP_RAD = np.radians(2.0)  # the joint path is checked every 2° of the joint that travels most


class CellModel:
    """Obstacles by name and the tool's capsules, checked against the arm at any joint angles by the
    simulator's own checker (`CellCheck`), so the ghost turns red exactly where the simulator refuses."""

    def __init__(
        self, arm: ArmModel, obstacles: Sequence[Obstacle], shape: ToolShape, tool: Tool | None = None
    ) -> None:
        self.arm = arm
        self.obstacles = list(obstacles)
        self.shape = shape
        named = []
        for obstacle in self.obstacles:
            try:
                named.append(NamedShape(obstacle.name, *obstacle_shape(obstacle)))
            except ControllerError:  # a plane on a line: the controller refuses it, so it never holds one
                continue
        capsules = tool_capsules(shape, tool if tool is not None else _NO_TOOL)
        self.check = CellCheck(arm, named, capsules)

    def collides(self, q: np.ndarray) -> bool:
        """The arm touches itself, the floor or an obstacle, or its tool the floor or an obstacle, at q."""
        return self.check.collides(q)

    def touching(self, q: np.ndarray) -> list[str]:
        """The names of the obstacles the arm or its tool touches at q."""
        return self.check.touching(q) or []

    def contacts(self, q: np.ndarray) -> Contacts:
        """Each obstacle (and the floor, for the tool) touching the arm or its tool at q: depth and links."""
        return self.check.contacts(q)

    def path_worse(self, q_from: np.ndarray, q_to: np.ndarray) -> Worse | None:
        """The first contact the joint-interpolated path from q_from to q_to (Move J's path, the target
        included) would make or deepen, or the arm touching itself or the floor on it (the contact rule,
        kinematics/contact.py); None if it may go."""
        samples = joint_samples(q_from, q_to, PATH_STEP_RAD)[1:]
        touching = self.check.collides_many(samples)  # one call; the depths only where something touches
        if not np.any(touching):
            return None
        guard = ContactGuard(self.check, q_from)
        for q, collides in zip(samples, touching, strict=True):
            worse = guard.check(q, bool(collides))
            if worse is not None:
                return worse
        return None


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
        cell = self._cell()
        return cell.collides(q) if cell is not None else self._arm.in_collision(q)

    def blocked_from(self, q_start: np.ndarray) -> Callable[[np.ndarray], bool]:
        """The test for the samples of one motion from q_start, in path order: the arm with itself and the
        floor, and the cell under the contact rule (an arm touching an obstacle may back out of it)."""
        cell = self._cell()
        if cell is None:
            return self._arm.in_collision
        guard = ContactGuard(cell.check, q_start)
        return lambda q: guard.check(q) is not None

    def __getattr__(self, name: str) -> Any:
        return getattr(self._arm, name)
