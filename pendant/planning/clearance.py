"""How close the arm and its tool come to the cell: `Clearance(q) -> Closest(mm, link, obstacle)`.

Asked of the ONE cell check (pendant/kinematics/cell_check.py), in the operator's words: the URDF's
collision shapes on the moving links by link, the tool's capsules (and the sphere at the TCP) as "the tool",
the gripper's fingers as "the gripper"; obstacles are the controller's, by name.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from pendant.controller.cell_types import Obstacle, ToolShape
from pendant.controller.types import Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import TOOL_LINK
from pendant.kinematics.cell_shapes import cell_check

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


class Clearance:
    """Distances from the arm (and tool) at q to each obstacle of the cell, on the shared cell check;
    `None` for an empty cell."""

    def __init__(
        self, arm: ArmModel, obstacles: Sequence[Obstacle], tool_shape: ToolShape, tool: Tool
    ) -> None:
        self._check = cell_check(arm, obstacles, tool_shape, tool)

    @property
    def empty(self) -> bool:
        return not self._check.obstacles

    def __call__(self, q: np.ndarray) -> Closest | None:
        closest = self._check.closest_obstacle(q)
        if closest is None:
            return None
        part = TOOL_NAME if closest.link == TOOL_LINK else part_name(closest.link)
        return Closest(closest.distance_m * 1000.0, part, closest.obstacle)
