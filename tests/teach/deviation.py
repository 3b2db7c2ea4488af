"""How far a played path strays from a recorded one: distances between sampled TCP points and polylines."""

from __future__ import annotations

import numpy as np


def distances_to_polyline(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """For each of `points` (n, 3), the distance to the nearest point of the polyline through `polyline`."""
    a, b = polyline[:-1], polyline[1:]
    seg = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-18)
    rel = points[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum("nmj,mj->nm", rel, seg) / length2, 0.0, 1.0)
    nearest = a[None, :, :] + t[:, :, None] * seg[None, :, :]
    return np.min(np.linalg.norm(points[:, None, :] - nearest, axis=2), axis=1)


def max_deviation_mm(recorded_m: np.ndarray, played_m: np.ndarray) -> tuple[float, float]:
    """(recorded samples -> played path, played samples -> recorded path), the largest distance in mm each."""
    there = distances_to_polyline(recorded_m, played_m)
    back = distances_to_polyline(played_m, recorded_m)
    return float(np.max(there)) * 1000.0, float(np.max(back)) * 1000.0


def from_rest_at(played_m: np.ndarray, start_m: np.ndarray, within_m: float = 1e-4) -> np.ndarray:
    """The played samples from the first one at the path's start (the approach to it dropped)."""
    at = np.flatnonzero(np.linalg.norm(played_m - start_m, axis=1) <= within_m)
    assert at.size, "the arm never reached the path's start"
    return played_m[at[0] :]
