"""Geometric paths s -> configuration, blended through waypoints.

A path is a chain of pieces with constant second derivative in s: straight segments between waypoints and,
at each interior waypoint, a parabolic blend that leaves the incoming segment and joins the outgoing one
with a continuous tangent (the linear-segment-with-parabolic-blend construction). The blend passes the
waypoint within a tolerance instead of stopping at it. The same construction serves joint space (y = q)
and Cartesian space (y = position and a rotation vector relative to the waypoint's orientation).
"""

from __future__ import annotations

import bisect
import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from pendant.kinematics.transforms import matrix_to_rotvec, rotvec_to_matrix

# How far a blended path may pass from an interior waypoint (documented in README).
JOINT_BLEND_TOL_RAD = np.radians(0.5)
CARTESIAN_BLEND_TOL_M = 1e-3
CARTESIAN_BLEND_TOL_RAD = np.radians(0.5)
# In a Cartesian path one radian of TCP turn counts like this many metres of travel when measuring s.
ROTATION_LENGTH_M_PER_RAD = 0.2


@dataclass(frozen=True)
class Pieces:
    """y(s) = base + y0 + v0 u + acc u^2 / 2 with u = s - start, piecewise; base is a waypoint index."""

    starts: list[float]
    base: list[int]
    y0: np.ndarray  # (n, dim)
    v0: np.ndarray
    acc: np.ndarray
    length: float
    blend: list[bool]

    def index(self, s: float) -> int:
        return max(0, min(len(self.starts) - 1, bisect.bisect_right(self.starts, s) - 1))

    def local(self, s: float) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
        k = self.index(s)
        u = s - self.starts[k]
        return (
            k,
            self.y0[k] + self.v0[k] * u + 0.5 * self.acc[k] * (u * u),
            self.v0[k] + self.acc[k] * u,
            self.acc[k],
        )

    def boundaries(self) -> list[float]:
        return [*self.starts, self.length]


def blended_pieces(deltas: np.ndarray, lengths: np.ndarray, blend_half: np.ndarray) -> Pieces:
    """Pieces through waypoints 0..n with segment j going by `deltas[j]` over path length `lengths[j]`.

    `blend_half[j]` (j = 1..n-1) is the half length of the blend at interior waypoint j (0: a sharp corner,
    only allowed where the tangent does not change).
    """
    n_seg, dim = deltas.shape
    tangents = deltas / lengths[:, None]
    corners = np.concatenate([[0.0], np.cumsum(lengths)])
    d = np.zeros(n_seg + 1)
    d[1:n_seg] = blend_half[1:n_seg]
    starts: list[float] = []
    base: list[int] = []
    y0: list[np.ndarray] = []
    v0: list[np.ndarray] = []
    acc: list[np.ndarray] = []
    blend: list[bool] = []
    zero = np.zeros(dim)
    for j in range(n_seg):
        if j > 0 and d[j] > 0.0:
            t1, t2 = tangents[j - 1], tangents[j]
            starts.append(float(corners[j] - d[j]))
            base.append(j)
            y0.append(-t1 * d[j])
            v0.append(t1)
            acc.append((t2 - t1) / (2.0 * d[j]))
            blend.append(True)
        start = corners[j] + d[j]
        end = corners[j + 1] - d[j + 1]
        if end > start or (j == n_seg - 1) or not starts:
            starts.append(float(start))
            base.append(j)
            y0.append(tangents[j] * d[j])
            v0.append(tangents[j])
            acc.append(zero)
            blend.append(False)
    return Pieces(
        starts=starts,
        base=base,
        y0=np.array(y0),
        v0=np.array(v0),
        acc=np.array(acc),
        length=float(corners[-1]),
        blend=blend,
    )


def _blend_half_lengths(tangents: np.ndarray, lengths: np.ndarray, d_limit: list[float]) -> np.ndarray:
    """Blend half lengths: the tolerance's limit, but never more than half of either adjacent segment."""
    n_seg = len(lengths)
    d = np.zeros(n_seg)
    for j in range(1, n_seg):
        if np.allclose(tangents[j - 1], tangents[j], atol=1e-12):
            continue
        d[j] = min(d_limit[j], 0.5 * lengths[j - 1], 0.5 * lengths[j])
    return d


def dedupe_waypoints(
    points: list[np.ndarray], distance: Callable[[np.ndarray, np.ndarray], float]
) -> list[int]:
    """The indices of the waypoints to keep: the first and each apart from the last one kept (the final
    waypoint stands in for a duplicate at the end)."""
    keep = [0]
    for i in range(1, len(points)):
        if distance(points[keep[-1]], points[i]) > 1e-12:
            keep.append(i)
    if len(keep) > 1 and keep[-1] != len(points) - 1:
        keep[-1] = len(points) - 1
    return keep


def waypoint_s_of(keep: list[int], corners: list[float], count: int) -> list[float]:
    """s at each of `count` original waypoints (a dropped duplicate sits where the one it repeats does)."""
    return [corners[max(0, bisect.bisect_right(keep, i) - 1)] for i in range(count)]


def _corner_tol(tol: float, blends: Sequence[float] | None, keep: list[int], j: int) -> float:
    """The corner tolerance at kept waypoint j: the waypoint's own blend, or the default where it has none
    (0), as the README documents `blend`. A blend below the default is kept too: a recorded path asks for
    half its tolerance (pendant.program.blended)."""
    if blends is None or blends[keep[j]] <= 0.0:
        return tol
    return float(blends[keep[j]])


class JointPath:
    """A joint-space path through waypoints q_0..q_n (radians), blended within JOINT_BLEND_TOL_RAD.

    s is measured in seconds at full joint speed: a segment's length is max_i |dq_i| / vmax_i, so
    ds/dt = 1 moves the leading joint at its speed limit.
    """

    def __init__(
        self,
        waypoints: np.ndarray,
        vmax: np.ndarray,
        tol_rad: float = JOINT_BLEND_TOL_RAD,
        blends_rad: Sequence[float] | None = None,
    ) -> None:
        """`blends_rad[i]`: how far (radians, per joint) the path may pass from waypoint i (a waypoint's
        `blend`; 0: `tol_rad`)."""
        waypoints = np.atleast_2d(np.asarray(waypoints, dtype=float))
        keep = dedupe_waypoints(list(waypoints), lambda a, b: float(np.max(np.abs(a - b))))
        self.waypoints = waypoints[keep]
        self.q_start = self.waypoints[0].copy()
        self.q_end = self.waypoints[-1].copy()
        if len(self.waypoints) < 2:
            self.pieces: Pieces | None = None
            self.length = 0.0
            self.waypoint_s = [0.0] * len(waypoints)
            return
        deltas = np.diff(self.waypoints, axis=0)
        lengths = np.max(np.abs(deltas) / vmax, axis=1)
        tangents = deltas / lengths[:, None]
        self.waypoint_s = waypoint_s_of(keep, [0.0, *np.cumsum(lengths).tolist()], len(waypoints))
        # Mid-blend deviation from the corner is |t2 - t1| d / 4 per joint.
        d_limit = [0.0] + [
            float(
                4.0
                * _corner_tol(tol_rad, blends_rad, keep, j)
                / max(np.max(np.abs(tangents[j] - tangents[j - 1])), 1e-12)
            )
            for j in range(1, len(lengths))
        ]
        self.pieces = blended_pieces(deltas, lengths, _blend_half_lengths(tangents, lengths, d_limit))
        self.length = self.pieces.length

    def q(self, s: float) -> np.ndarray:
        if self.pieces is None:
            return self.q_start.copy()
        k, y, _, _ = self.pieces.local(s)
        return self.waypoints[self.pieces.base[k]] + y

    def derivatives(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, dq/ds, d2q/ds2) at s."""
        if self.pieces is None:
            zero = np.zeros_like(self.q_start)
            return self.q_start.copy(), zero, zero
        k, y, dy, ddy = self.pieces.local(s)
        return self.waypoints[self.pieces.base[k]] + y, dy, ddy

    def grid(self, max_step: float) -> np.ndarray:
        """Grid points on [0, L]: every piece boundary, and no cell longer than max_step."""
        if self.pieces is None:
            return np.array([0.0])
        return refine_grid(self.pieces.boundaries(), max_step)


class CartesianPath:
    """A TCP path through poses T_0..T_n (4x4): straight lines with slerped orientation, blended at
    interior poses within CARTESIAN_BLEND_TOL_M / CARTESIAN_BLEND_TOL_RAD.

    s is in metres: a segment's length is max(|dp|, ROTATION_LENGTH_M_PER_RAD * turn angle).
    """

    def __init__(self, poses: list[np.ndarray], blends_m: Sequence[float] | None = None) -> None:
        """`blends_m[i]`: how far (metres) the path may pass from pose i (a waypoint's `blend`; 0: the
        default tolerance); the orientation may deviate in proportion, and at least by the default."""

        def distance(a: np.ndarray, b: np.ndarray) -> float:
            return max(
                float(np.linalg.norm(a[:3, 3] - b[:3, 3])),
                float(np.linalg.norm(matrix_to_rotvec(b[:3, :3] @ a[:3, :3].T))),
            )

        keep = dedupe_waypoints(poses, distance)
        self.poses = [np.asarray(poses[i], dtype=float) for i in keep]
        self.positions = np.array([T[:3, 3] for T in self.poses])
        self.rotations = [T[:3, :3] for T in self.poses]
        if len(self.poses) < 2:
            self.pieces: Pieces | None = None
            self.length = 0.0
            self.waypoint_s = [0.0] * len(poses)
            return
        deltas = np.array(
            [
                np.concatenate(
                    [
                        self.positions[j + 1] - self.positions[j],
                        matrix_to_rotvec(self.rotations[j + 1] @ self.rotations[j].T),
                    ]
                )
                for j in range(len(self.poses) - 1)
            ]
        )
        lengths = np.maximum(
            np.linalg.norm(deltas[:, :3], axis=1),
            ROTATION_LENGTH_M_PER_RAD * np.linalg.norm(deltas[:, 3:], axis=1),
        )
        tangents = deltas / lengths[:, None]
        self.waypoint_s = waypoint_s_of(keep, [0.0, *np.cumsum(lengths).tolist()], len(poses))
        d_limit = [0.0]
        for j in range(1, len(lengths)):
            dt = tangents[j] - tangents[j - 1]
            tol_m = _corner_tol(CARTESIAN_BLEND_TOL_M, blends_m, keep, j)
            tol_rad = max(CARTESIAN_BLEND_TOL_RAD, tol_m / ROTATION_LENGTH_M_PER_RAD)
            d_pos = 4.0 * tol_m / max(float(np.linalg.norm(dt[:3])), 1e-12)
            d_rot = 4.0 * tol_rad / max(float(np.linalg.norm(dt[3:])), 1e-12)
            d_limit.append(min(d_pos, d_rot))
        self.pieces = blended_pieces(deltas, lengths, _blend_half_lengths(tangents, lengths, d_limit))
        self.length = self.pieces.length

    def pose(self, s: float) -> np.ndarray:
        """T_base_tcp at s."""
        T = np.eye(4)
        if self.pieces is None:
            return self.poses[0].copy()
        k, y, _, _ = self.pieces.local(s)
        j = self.pieces.base[k]
        T[:3, 3] = self.positions[j] + y[:3]
        T[:3, :3] = rotvec_to_matrix(y[3:]) @ self.rotations[j]
        return T

    def grid(self, max_step: float) -> np.ndarray:
        """Every piece boundary, and no cell longer than max_step; a blend shorter than two cells gets its
        middle too: the joint path is linear between samples, and a chord across a whole blend would cut the
        corner by twice its tolerance."""
        if self.pieces is None:
            return np.array([0.0])
        return refine_grid(self.pieces.boundaries(), max_step, self.pieces.blend)


def refine_grid(boundaries: list[float], max_step: float, halved: list[bool] | None = None) -> np.ndarray:
    """The boundaries plus evenly spaced points so that no cell is longer than max_step (and the cells
    marked in `halved` are split at least in two)."""
    points: list[np.ndarray] = []
    for k, (a, b) in enumerate(itertools.pairwise(boundaries)):
        if b <= a:
            continue
        n = max(2 if halved is not None and halved[k] else 1, int(np.ceil((b - a) / max_step)))
        points.append(np.linspace(a, b, n + 1)[:-1])
    points.append(np.array([boundaries[-1]]))
    return np.concatenate(points)
