"""The controller's obstacles and tool shape as coal shapes: one builder for the simulator's checks and the
page's, so the ghost turns red exactly where the simulator refuses."""

from __future__ import annotations

from collections.abc import Iterable

import coal
import numpy as np

from pendant.controller.cell_types import (
    MSG_PLANE_ON_A_LINE,
    BoxObstacle,
    CapsuleObstacle,
    Obstacle,
    PlaneObstacle,
    ToolShape,
)
from pendant.controller.errors import PreconditionFailed
from pendant.controller.types import Point, Tool
from pendant.kinematics.arm_model import ArmModel
from pendant.kinematics.cell_check import CellCheck, NamedShape
from pendant.kinematics.obstacles import Capsule, box_shape, capsule_shape, plane_shape
from pendant.kinematics.transforms import position_to_matrix


def vector(point: Point) -> np.ndarray:
    return np.array([point.x, point.y, point.z])


def obstacle_shape(obstacle: Obstacle) -> tuple[coal.CollisionGeometry, np.ndarray]:
    """The obstacle's coal shape and its pose in the base frame; PreconditionFailed for a plane whose
    points lie on one line (the controller refuses it, with this message)."""
    if isinstance(obstacle, BoxObstacle):
        return box_shape(vector(obstacle.sides), position_to_matrix(obstacle.centerPosition))
    if isinstance(obstacle, CapsuleObstacle):
        return capsule_shape(Capsule(obstacle.radius, vector(obstacle.begin), vector(obstacle.finish)))
    assert isinstance(obstacle, PlaneObstacle)
    shape = plane_shape(np.array([vector(p) for p in obstacle.points]))
    if shape is None:
        raise PreconditionFailed(MSG_PLANE_ON_A_LINE)
    return shape


def tool_capsules(shape: ToolShape, tool: Tool) -> list[Capsule]:
    """The tool's capsules in the flange frame, with the tool's sphere at the TCP when it has a radius."""
    capsules = [Capsule(c.radius, vector(c.begin), vector(c.finish)) for c in shape.shape]
    if tool.radius > 0.0:  # the reference's tool sphere at the TCP belongs to the same tool
        tcp = vector(tool.point)
        capsules.append(Capsule(tool.radius, tcp, tcp))
    return capsules


def cell_check(arm: ArmModel, obstacles: Iterable[Obstacle], shape: ToolShape, tool: Tool) -> CellCheck:
    """The collision checker of this cell: the obstacles (a plane on a line is PreconditionFailed), the tool
    shape and the tool's sphere."""
    named = [NamedShape(o.name, *obstacle_shape(o)) for o in obstacles]
    return CellCheck(arm, named, tool_capsules(shape, tool))
