"""How far a played path strays from a recorded one: distances between sampled TCP points and polylines."""

from __future__ import annotations

import numpy as np

from pendant.kinematics.transforms import matrix_to_rotvec, rotation_angle, rotvec_to_matrix


def distances_to_polyline(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """For each of `points` (n, 3), the distance to the nearest point of the polyline through `polyline`."""
    a, b = polyline[:-1], polyline[1:]
    seg = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-18)
    rel = points[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum("nmj,mj->nm", rel, seg) / length2, 0.0, 1.0)
    nearest = a[None, :, :] + t[:, :, None] * seg[None, :, :]
    return np.min(np.linalg.norm(points[:, None, :] - nearest, axis=2), axis=1)


def coverage_mm(recorded_m: np.ndarray, played_m: np.ndarray) -> float:
    """How far (mm) the played path passed from the recorded sample it missed most, where the played path is
    known only at samples: each distance to a chord between two played samples counts less half that chord's
    length, since the arm may have been anywhere that close to it between the two readings (a reading held up
    by a loaded machine can span a corner)."""
    a, b = played_m[:-1], played_m[1:]
    seg = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-18)
    rel = recorded_m[:, None, :] - a[None, :, :]
    t = np.clip(np.einsum("nmj,mj->nm", rel, seg) / length2, 0.0, 1.0)
    distance = np.linalg.norm(
        recorded_m[:, None, :] - (a[None, :, :] + t[:, :, None] * seg[None, :, :]), axis=2
    )
    slack = np.sqrt(length2) / 2.0
    return float(np.max(np.maximum(np.min(distance - slack[None, :], axis=1), 0.0))) * 1000.0


def max_deviation_mm(recorded_m: np.ndarray, played_m: np.ndarray) -> tuple[float, float]:
    """(recorded samples -> played path, played samples -> recorded path), the largest distance in mm each."""
    there = distances_to_polyline(recorded_m, played_m)
    back = distances_to_polyline(played_m, recorded_m)
    return float(np.max(there)) * 1000.0, float(np.max(back)) * 1000.0


def start_index(played_m: np.ndarray, start_m: np.ndarray, within_m: float = 1e-4) -> int:
    """The first played sample at the path's start: the samples before it are the approach."""
    at = np.flatnonzero(np.linalg.norm(played_m - start_m, axis=1) <= within_m)
    assert at.size, "the arm never reached the path's start"
    return int(at[0])


def from_rest_at(played_m: np.ndarray, start_m: np.ndarray, within_m: float = 1e-4) -> np.ndarray:
    """The played samples from the first one at the path's start (the approach to it dropped)."""
    return played_m[start_index(played_m, start_m, within_m) :]


def max_turn_deg(recorded: np.ndarray, played: np.ndarray) -> float:
    """The largest angle (degrees) between a played TCP orientation and the recorded one at the nearest point
    of the recorded path (slerped along its segment): poses are 4x4 matrices, (n, 4, 4)."""
    a, b = recorded[:-1, :3, 3], recorded[1:, :3, 3]
    seg = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", seg, seg), 1e-18)
    worst = 0.0
    for T in played:
        t = np.clip(np.einsum("mj,mj->m", T[:3, 3] - a, seg) / length2, 0.0, 1.0)
        k = int(np.argmin(np.linalg.norm(a + t[:, None] * seg - T[:3, 3], axis=1)))
        R_a, R_b = recorded[k, :3, :3], recorded[k + 1, :3, :3]
        expected = rotvec_to_matrix(t[k] * matrix_to_rotvec(R_b @ R_a.T)) @ R_a
        worst = max(worst, rotation_angle(expected, T[:3, :3]))
    return float(np.degrees(worst))
