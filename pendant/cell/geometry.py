"""The controller's cell as coal geometry in the pendant, so the page checks what the controller checks.

Built with the simulator's own shape builders: the ghost turns red exactly where the simulator refuses.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import coal
import numpy as np

from pendant.controller import ControllerError, Point, Rotation, Tool
from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_shapes import obstacle_shape, tool_capsules
from pendant.kinematics.contact import ContactGuard, Contacts, Worse
from pendant.kinematics.obstacles import CellGeometry, bounding_sphere, capsule_shape, collide

PATH_STEP_RAD = np.radians(2.0)  # the joint path is checked every 2° of the joint that travels most


class CellModel:
    """Obstacles by name and the tool's capsules, checked against the arm at any joint angles.

    Same shapes and the same narrow-phase test as the simulator (its `CellGeometry`), with a bounding-sphere
    test first: most link-obstacle pairs are far apart, and the ghost checks a whole path on every drag.
    """

    def __init__(
        self, arm: ArmModel, obstacles: Sequence[Obstacle], shape: ToolShape, tool: Tool | None = None
    ) -> None:
        self.arm = arm
        self.obstacles = list(obstacles)
        self.shape = shape
        capsules = tool_capsules(shape, tool if tool is not None else _NO_TOOL)
        self._floor = CellGeometry(arm, [], capsules)  # the tool against the floor (no obstacles: fast)
        self._tool = [capsule_shape(capsule) for capsule in capsules]
        self._shapes: list[tuple[str, coal.CollisionGeometry, np.ndarray]] = []
        centres, radii = [], []
        for obstacle in self.obstacles:
            try:
                geometry, T = obstacle_shape(obstacle)
            except ControllerError:  # a plane on a line: the controller refuses it, so it never holds one
                continue
            centre, radius = bounding_sphere(geometry, T)
            self._shapes.append((obstacle.name, geometry, T))
            centres.append(centre)
            radii.append(radius)
        self._centres = np.array(centres).reshape(-1, 3)
        self._radii = np.array(radii)
        # The simulator's own checker over the same shapes: depths and links for the contact rule.
        self.geometry = CellGeometry(
            arm, [(g, T) for _, g, T in self._shapes], capsules, [name for name, _, _ in self._shapes]
        )

    def _hits(self, q: np.ndarray, *, all_of_them: bool) -> list[str]:
        if not self._shapes:
            return []
        T_base_flange = self.arm.fk(q)
        moving = [*self.arm.moving_shapes(q), *((s, T_base_flange @ T) for s, T in self._tool)]
        # Each coal shape keeps its local bounding sphere once computed (pinocchio hands out a new Python
        # wrapper of the same shape on every call: a cache keyed by the wrapper grew by every check).
        spheres = [bounding_sphere(link, T_link) for link, T_link in moving]
        centres = [centre for centre, _ in spheres]
        radii = [radius for _, radius in spheres]
        gaps = np.linalg.norm(np.asarray(centres)[:, None, :] - self._centres[None, :, :], axis=2)
        near = gaps <= np.asarray(radii)[:, None] + self._radii[None, :]  # planes (infinite) always
        hit: list[str] = []
        for i, j in zip(*np.nonzero(near), strict=True):
            name, obstacle, T_obstacle = self._shapes[j]
            if name in hit:
                continue
            link, T_link = moving[i]
            if collide(link, T_link, obstacle, T_obstacle):
                hit.append(name)
                if not all_of_them:
                    return hit
        return hit

    def collides(self, q: np.ndarray) -> bool:
        """The arm or its tool touches an obstacle, or the tool dips below the floor, at q."""
        return self._floor.collides(q) or bool(self._hits(q, all_of_them=False))

    def touching(self, q: np.ndarray) -> list[str]:
        """The names of the obstacles the arm or its tool touches at q."""
        return self._hits(q, all_of_them=True)

    def contacts(self, q: np.ndarray) -> Contacts:
        """Each obstacle (and the floor, for the tool) touching the arm or its tool at q: depth and links."""
        return self.geometry.contacts(q)

    def path_worse(self, q_from: np.ndarray, q_to: np.ndarray) -> Worse | None:
        """The first contact the joint-interpolated path from q_from to q_to (Move J's path, the target
        included) would make or deepen (the contact rule, kinematics/contact.py); None if it may go."""
        if self.geometry.empty:
            return None
        steps = max(1, int(np.ceil(float(np.max(np.abs(q_to - q_from))) / PATH_STEP_RAD)))
        guard = ContactGuard(self, q_from)
        for fraction in np.linspace(0.0, 1.0, steps + 1)[1:]:
            worse = guard.check(q_from + fraction * (q_to - q_from))
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
        if self._arm.in_collision(q):
            return True
        cell = self._cell()
        return cell is not None and cell.collides(q)

    def blocked_from(self, q_start: np.ndarray) -> Callable[[np.ndarray], bool]:
        """The test for the samples of one motion from q_start, in path order: the arm with itself and the
        floor, and the cell under the contact rule (an arm touching an obstacle may back out of it)."""
        cell = self._cell()
        if cell is None:
            return self._arm.in_collision
        guard = ContactGuard(cell, q_start)
        return lambda q: self._arm.in_collision(q) or guard.check(q) is not None

    def __getattr__(self, name: str) -> Any:
        return getattr(self._arm, name)
