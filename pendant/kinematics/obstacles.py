"""Obstacles in the cell and the tool's capsules as coal shapes (checked by `cell_check.CellCheck`).

numpy in, numpy out: obstacles are given in the arm's base frame, the tool's capsules in the flange frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import coal
import numpy as np

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
