"""Whether a sphere of the work is wholly inside a pinhole camera's view: how Fit view's camera is checked
(tests/ui/test_framing.py, tests/ui/test_view_fit_startup.py), z up as the scene is."""

from __future__ import annotations

import math

import numpy as np

FOV_RAD = math.radians(50.0)
HOME_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)


def in_view(
    position: np.ndarray, look_at: np.ndarray, point: np.ndarray, radius: float, aspect: float
) -> bool:
    """The sphere wholly inside a pinhole camera's view (z up, vertical field FOV_RAD)."""
    forward = (look_at - position) / np.linalg.norm(look_at - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = point - position
    depth = float(d @ forward)
    tan_v = math.tan(FOV_RAD / 2)
    tan_h = tan_v * aspect
    # The sphere's edge, pushed out sideways and up by its radius (a slightly generous bound).
    return (
        depth > radius
        and abs(float(d @ right)) + radius <= depth * tan_h
        and abs(float(d @ up)) + radius <= depth * tan_v
    )
