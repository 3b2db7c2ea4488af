"""Fit: the camera placed so the arm, its tool and every obstacle of the cell are in the 3D view, whatever the
view's shape (issue 33: on an upright tablet the view cut a box and the tool at its left edge).

Everything to frame is a sphere around it (the arm's joints, the TCP, each box and capsule; a plane has no
size and is left out); the camera keeps the pendant's usual direction (front right, from above) and backs off
until the spheres' enclosing sphere fits the narrower of the view's two angles.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pendant.controller.cell_types import BoxObstacle, CapsuleObstacle, Obstacle

JOINT_RADIUS_M = 0.08  # the arm's links around each joint's frame
TCP_RADIUS_M = 0.05
MARGIN = 1.1  # a little room between the work and the view's edges
Sphere = tuple[np.ndarray, float]


def obstacle_spheres(obstacles: Sequence[Obstacle]) -> list[Sphere]:
    spheres: list[Sphere] = []
    for o in obstacles:
        if isinstance(o, BoxObstacle):
            p, s = o.centerPosition.point, o.sides
            spheres.append((np.array([p.x, p.y, p.z]), 0.5 * math.hypot(s.x, s.y, s.z)))
        elif isinstance(o, CapsuleObstacle):
            a = np.array([o.begin.x, o.begin.y, o.begin.z])
            b = np.array([o.finish.x, o.finish.y, o.finish.z])
            spheres.append(((a + b) / 2, float(np.linalg.norm(b - a)) / 2 + o.radius))
    return spheres


def arm_spheres(frames: np.ndarray, tcp: np.ndarray) -> list[Sphere]:
    """`frames`: T_base_i of the arm's joints (n, 4, 4); `tcp`: the tool's TCP point."""
    spheres: list[Sphere] = [(np.asarray(T[:3, 3], dtype=float), JOINT_RADIUS_M) for T in frames]
    spheres.append((np.asarray(tcp, dtype=float), TCP_RADIUS_M))
    return spheres


def fit_camera(
    spheres: Sequence[Sphere], direction: np.ndarray, vertical_fov_rad: float, aspect: float
) -> tuple[np.ndarray, np.ndarray]:
    """(camera position, look-at point): looking along -`direction` at the spheres' middle, far enough back
    that all of them are in view (aspect: the view's width over its height)."""
    if not spheres:
        raise ValueError("nothing to frame")
    low = np.min([c - r for c, r in spheres], axis=0)
    high = np.max([c + r for c, r in spheres], axis=0)
    middle = (low + high) / 2
    radius = max(float(np.linalg.norm(c - middle)) + r for c, r in spheres)
    half_vertical = vertical_fov_rad / 2
    half_horizontal = math.atan(math.tan(half_vertical) * aspect)
    distance = MARGIN * radius / math.sin(min(half_vertical, half_horizontal))
    unit = np.asarray(direction, dtype=float) / float(np.linalg.norm(direction))
    return middle + unit * distance, middle
