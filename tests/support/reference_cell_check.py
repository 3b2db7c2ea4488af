"""The cell check as it was before pendant.kinematics.cell_check (a Python loop over coal pairs behind
bounding spheres, plus the arm's own check): the reference the new checker is compared with, nothing else."""

from __future__ import annotations

import math
from dataclasses import dataclass

import coal
import numpy as np

from pendant.kinematics.arm_model import ArmModel
from pendant.kinematics.obstacles import Capsule, capsule_shape

FLOOR_Z_M = 0.0


def bounding_sphere(shape: coal.CollisionGeometry, T: np.ndarray) -> tuple[np.ndarray, float]:
    """Centre (base frame) and radius of a sphere holding the shape; a half-space gets an infinite one."""
    if isinstance(shape, coal.Halfspace):
        return T[:3, 3], math.inf
    if shape.aabb_radius < 0:
        shape.computeLocalAABB()
    return T[:3, :3] @ shape.aabb_center + T[:3, 3], float(shape.aabb_radius)


def _apart(shape: coal.CollisionGeometry, T: np.ndarray, obstacle: _Placed) -> bool:
    """Cheap broad phase: the two surely do not touch (bounding spheres apart, or clear of the plane)."""
    centre, radius = bounding_sphere(shape, T)
    if obstacle.plane is not None:
        normal, offset = obstacle.plane
        return float(normal @ centre) - offset > radius  # wholly on the free side
    return float(np.linalg.norm(centre - obstacle.centre)) > radius + obstacle.radius


@dataclass(frozen=True)
class _Placed:
    shape: coal.CollisionGeometry
    T: np.ndarray
    centre: np.ndarray
    radius: float
    plane: tuple[np.ndarray, float] | None  # a half-space's normal and offset (free side: n.x > d)


def _placed(shape: coal.CollisionGeometry, T: np.ndarray) -> _Placed:
    if isinstance(shape, coal.Halfspace):
        normal = np.array(shape.n)
        return _Placed(shape, T, T[:3, 3], math.inf, (normal, float(shape.d)))
    centre, radius = bounding_sphere(shape, T)
    return _Placed(shape, T, centre, radius, None)


def collide(a: coal.CollisionGeometry, T_a: np.ndarray, b: coal.CollisionGeometry, T_b: np.ndarray) -> bool:
    request = coal.CollisionRequest()
    result = coal.CollisionResult()
    return coal.collide(a, _transform(T_a), b, _transform(T_b), request, result) > 0


def _transform(T: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))


class CellGeometry:
    """Obstacles and tool capsules for one arm; immutable (a change makes a new one)."""

    def __init__(
        self,
        arm: ArmModel,
        obstacles: list[tuple[coal.CollisionGeometry, np.ndarray]],
        tool: list[Capsule],
    ) -> None:
        self.arm = arm
        self.obstacles = obstacles
        self._placed = [_placed(shape, T) for shape, T in obstacles]
        self.tool = tool
        self._tool_shapes = [capsule_shape(capsule) for capsule in tool]

    @property
    def empty(self) -> bool:
        return not self.obstacles and not self.tool

    def collides(self, q: np.ndarray) -> bool:
        """The arm's moving links or the tool touch an obstacle, or the tool dips below the floor, at q."""
        if self.empty:
            return False
        T_base_flange = self.arm.fk(q)
        tool = [(shape, T_base_flange @ T) for shape, T in self._tool_shapes]
        for capsule in self.tool:
            for end in (capsule.a, capsule.b):
                if (T_base_flange[:3, :3] @ end + T_base_flange[:3, 3])[2] - capsule.radius < FLOOR_Z_M:
                    return True
        if not self.obstacles:
            return False
        moving = [*self.arm.moving_shapes(q), *tool]
        return any(
            not _apart(shape, T_shape, obstacle) and collide(shape, T_shape, obstacle.shape, obstacle.T)
            for obstacle in self._placed
            for shape, T_shape in moving
        )

    def obstacle_collides(self, index: int, q: np.ndarray) -> bool:
        """Obstacle `index` alone touches the arm or the tool at q (adding it would trap the arm)."""
        return CellGeometry(self.arm, [self.obstacles[index]], self.tool).collides(q)
