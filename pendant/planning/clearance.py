"""How close the arm and its tool come to the cell: `Clearance(q) -> Closest(mm, link, obstacle)`.

One small class on coal's distance queries, so the pre-flight can later sit on the shared (pinocchio)
checker without changing its callers. The arm's shapes are the URDF's collision shapes on the moving links,
the tool's are its capsules (and the sphere at the TCP); obstacles are the controller's, by name.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import coal
import numpy as np

from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.types import Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_shapes import obstacle_shape, tool_capsules
from pendant.kinematics.obstacles import capsule_shape

TOOL_NAME = "the tool"
GRIPPER_NAME = "the gripper"
_SHAPE_SUFFIX = re.compile(r"_\d+$")


def part_name(shape: str) -> str:
    """A URDF collision shape's name as the operator says it: "link3_1" -> "link3", fingers -> the gripper."""
    link = _SHAPE_SUFFIX.sub("", shape)
    return GRIPPER_NAME if link.startswith(("gripper", "finger")) else link


@dataclass(frozen=True)
class Closest:
    """The closest approach at one configuration: millimetres (<= 0: touching), which part, which obstacle."""

    mm: float
    link: str
    obstacle: str


def _transform(T: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))


class Clearance:
    """Distances from the arm (and tool) at q to each obstacle of the cell; `None` for an empty cell."""

    def __init__(
        self, arm: ArmModel, obstacles: Sequence[Obstacle], tool_shape: ToolShape, tool: Tool
    ) -> None:
        self._arm = arm
        self._links = [part_name(name) for name in arm.moving_shape_names()]
        self._obstacles = [(o.name, *obstacle_shape(o)) for o in obstacles]
        self._tool = [capsule_shape(c) for c in tool_capsules(tool_shape, tool)]

    @property
    def empty(self) -> bool:
        return not self._obstacles

    def __call__(self, q: np.ndarray) -> Closest | None:
        if not self._obstacles:
            return None
        T_flange = self._arm.fk(q)
        parts: list[tuple[str, coal.CollisionGeometry, np.ndarray]] = [
            (link, shape, T) for link, (shape, T) in zip(self._links, self._arm.moving_shapes(q), strict=True)
        ]
        parts.extend((TOOL_NAME, shape, T_flange @ T) for shape, T in self._tool)
        best: Closest | None = None
        request = coal.DistanceRequest()
        for name, obstacle, T_obstacle in self._obstacles:
            placed = _transform(T_obstacle)
            for link, shape, T in parts:
                result = coal.DistanceResult()
                distance = coal.distance(shape, _transform(T), obstacle, placed, request, result)
                if best is None or distance * 1000.0 < best.mm:
                    best = Closest(float(distance) * 1000.0, link, name)
        return best
