"""Obstacles in the cell and the tool's capsules as coal shapes, checked against the arm's moving links.

numpy in, numpy out: obstacles are given in the arm's base frame, the tool's capsules in the flange frame.
The base link is not checked (it never moves: an obstacle touching it would block every motion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import coal
import numpy as np

from pendant.kinematics.arm_model import ArmModel
from pendant.kinematics.contact import FLOOR, Contact

FLOOR_Z_M = 0.0
TOOL_LINK = "tool"  # the link name the tool's capsules report in a contact
# The plane side that holds this point (just above the base) is free; the other side is solid.
_FREE_POINT = np.array([0.0, 0.0, 0.1])


@dataclass(frozen=True)
class Capsule:
    """A segment a-b swept by a sphere of `radius` (a == b: a sphere)."""

    radius: float
    a: np.ndarray
    b: np.ndarray


def box_shape(sides: np.ndarray, T_base_box: np.ndarray) -> tuple[coal.CollisionGeometry, np.ndarray]:
    return coal.Box(*(float(v) for v in sides)), T_base_box


def capsule_shape(capsule: Capsule) -> tuple[coal.CollisionGeometry, np.ndarray]:
    """A coal capsule (or sphere) and its pose: centred between the ends, z along a-b."""
    axis = capsule.b - capsule.a
    length = float(np.linalg.norm(axis))
    T = np.eye(4)
    T[:3, 3] = 0.5 * (capsule.a + capsule.b)
    if length < 1e-9:
        return coal.Sphere(max(capsule.radius, 1e-9)), T
    z = axis / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    return coal.Capsule(max(capsule.radius, 1e-9), length), T


def plane_shape(points: np.ndarray) -> tuple[coal.CollisionGeometry, np.ndarray] | None:
    """The solid half-space beyond the plane through the first three points; None if they are on a line."""
    p0, p1, p2 = points[:3]
    normal = np.cross(p1 - p0, p2 - p0)
    norm = float(np.linalg.norm(normal))
    if norm < 1e-9:
        return None
    normal /= norm
    offset = float(normal @ p0)
    # coal's half-space {x : n.x <= d} is the solid side: the free point must stay out of it.
    if normal @ _FREE_POINT <= offset:
        normal, offset = -normal, -offset
    return coal.Halfspace(normal, offset), np.eye(4)


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


def penetration(
    a: coal.CollisionGeometry, T_a: np.ndarray, b: coal.CollisionGeometry, T_b: np.ndarray
) -> float:
    """How deep the two shapes overlap (metres; 0 when they only graze): coal's signed distance, negated."""
    request = coal.DistanceRequest()
    result = coal.DistanceResult()
    return max(0.0, -coal.distance(a, _transform(T_a), b, _transform(T_b), request, result))


def _transform(T: np.ndarray) -> coal.Transform3s:
    return coal.Transform3s(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))


class CellGeometry:
    """Obstacles and tool capsules for one arm; immutable (a change makes a new one). `names`: the
    obstacles' names, for `contacts` (default: their indices as text)."""

    def __init__(
        self,
        arm: ArmModel,
        obstacles: list[tuple[coal.CollisionGeometry, np.ndarray]],
        tool: list[Capsule],
        names: list[str] | None = None,
    ) -> None:
        self.arm = arm
        self.obstacles = obstacles
        self.names = names if names is not None else [str(i) for i in range(len(obstacles))]
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
        if self._tool_floor_depth(T_base_flange) > 0.0:
            return True
        if not self.obstacles:
            return False
        moving = [*self.arm.moving_shapes(q), *self._tool_at(T_base_flange)]
        return any(
            not _apart(shape, T_shape, obstacle) and collide(shape, T_shape, obstacle.shape, obstacle.T)
            for obstacle in self._placed
            for shape, T_shape in moving
        )

    def contacts(self, q: np.ndarray) -> dict[str | None, Contact]:
        """Every obstacle (and the floor, for the tool) touching the arm or the tool at q: how deep, which
        links (the contact rule's query, see contact.py)."""
        found: dict[str | None, Contact] = {}
        if self.empty:
            return found
        T_base_flange = self.arm.fk(q)
        floor_depth = self._tool_floor_depth(T_base_flange)
        if floor_depth > 0.0:
            found[FLOOR] = Contact(floor_depth, (TOOL_LINK,))
        links = [*self.arm.moving_links(), *([TOOL_LINK] * len(self._tool_shapes))]
        moving = [*self.arm.moving_shapes(q), *self._tool_at(T_base_flange)]
        for name, obstacle in zip(self.names, self._placed, strict=True):
            depth, touched = 0.0, []
            for link, (shape, T_shape) in zip(links, moving, strict=True):
                if _apart(shape, T_shape, obstacle) or not collide(
                    shape, T_shape, obstacle.shape, obstacle.T
                ):
                    continue
                depth = max(depth, penetration(shape, T_shape, obstacle.shape, obstacle.T))
                if link not in touched:
                    touched.append(link)
            if touched:
                found[name] = Contact(depth, tuple(touched))
        return found

    def _tool_at(self, T_base_flange: np.ndarray) -> list[tuple[coal.CollisionGeometry, np.ndarray]]:
        return [(shape, T_base_flange @ T) for shape, T in self._tool_shapes]

    def _tool_floor_depth(self, T_base_flange: np.ndarray) -> float:
        """How far the tool's capsules reach below the floor (0 when they stay above it)."""
        depth = 0.0
        for capsule in self.tool:
            for end in (capsule.a, capsule.b):
                z = (T_base_flange[:3, :3] @ end + T_base_flange[:3, 3])[2]
                depth = max(depth, FLOOR_Z_M - (z - capsule.radius))
        return depth
