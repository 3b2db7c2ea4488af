"""Ramer-Douglas-Peucker in position and orientation: keep the fewest samples that reproduce the path.

A sample is dropped when, seen from the segment between the kept samples around it, it is within `tol_mm`
of the straight line and within `tol_deg` of the rotation interpolated (slerp) at its place along it.
"""

from __future__ import annotations

import numpy as np
import viser.transforms as vtf

MAX_WAYPOINTS = 100
DEFAULT_TOL_MM = 1.0
DEFAULT_TOL_DEG = 1.0
_MAX_RELAXATIONS = 30  # each one grows the tolerance by half: 1 mm becomes ~190 m (never reached)


def _worst(
    points_mm: np.ndarray, rotations: vtf.SO3, a: int, b: int, tol_mm: float, tol_deg: float
) -> tuple[int, float]:
    """The sample between a and b furthest off the segment (relative to the tolerances), and that ratio."""
    inner = np.arange(a + 1, b)
    seg = points_mm[b] - points_mm[a]
    length2 = float(seg @ seg)
    rel = points_mm[inner] - points_mm[a]
    t = np.clip(rel @ seg / length2, 0.0, 1.0) if length2 > 1e-12 else (inner - a) / (b - a)
    off_mm = np.linalg.norm(rel - np.outer(t, seg), axis=1)
    R_a = vtf.SO3(rotations.wxyz[a])
    delta = (R_a.inverse() @ vtf.SO3(rotations.wxyz[b])).log()
    slerp = R_a @ vtf.SO3.exp(np.asarray(t)[:, None] * delta[None, :])
    off_deg = np.degrees(np.linalg.norm((slerp.inverse() @ vtf.SO3(rotations.wxyz[inner])).log(), axis=1))
    ratio = np.maximum(off_mm / tol_mm, off_deg / tol_deg)
    i = int(np.argmax(ratio))
    return int(inner[i]), float(ratio[i])


def simplify(points_mm: np.ndarray, rotations: vtf.SO3, tol_mm: float, tol_deg: float) -> list[int]:
    """Indices of the samples to keep (first and last always), every dropped one within the tolerances."""
    n = len(points_mm)
    if n <= 2:
        return list(range(n))
    keep = {0, n - 1}
    stack = [(0, n - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        i, ratio = _worst(points_mm, rotations, a, b, tol_mm, tol_deg)
        if ratio > 1.0:
            keep.add(i)
            stack += [(a, i), (i, b)]
    return sorted(keep)


def simplify_to(
    points_mm: np.ndarray,
    rotations: vtf.SO3,
    tol_mm: float = DEFAULT_TOL_MM,
    tol_deg: float = DEFAULT_TOL_DEG,
    max_points: int = MAX_WAYPOINTS,
) -> tuple[list[int], float, float]:
    """`simplify` within at most `max_points`: when the path needs more at the asked tolerance, the tolerance
    is relaxed (x1.5 at a time) until it fits. Returns the indices and the tolerances used."""
    if tol_mm <= 0.0 or tol_deg <= 0.0:
        raise ValueError("the tolerances must be more than 0")
    for _ in range(_MAX_RELAXATIONS):
        kept = simplify(points_mm, rotations, tol_mm, tol_deg)
        if len(kept) <= max_points:
            return kept, tol_mm, tol_deg
        tol_mm, tol_deg = tol_mm * 1.5, tol_deg * 1.5
    raise ValueError("the path cannot be reduced to the waypoint limit")
