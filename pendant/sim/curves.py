"""Joint paths that are not built from blended pieces: one known at samples (what IK along a Cartesian path
gives) and a smooth spline through every waypoint (what PUT /poses/run follows). Same interface as
pendant.sim.paths.JointPath: q(s), derivatives(s), length, q_start, q_end."""

from __future__ import annotations

import bisect

import numpy as np

from pendant.sim.paths import dedupe_waypoints, refine_grid, waypoint_s_of


class SampledJointPath:
    """A joint path known at samples (s_k, q_k), linear in between: what IK along a Cartesian path gives."""

    def __init__(self, s: np.ndarray, q: np.ndarray) -> None:
        self.s = np.asarray(s, dtype=float)
        self.q_samples = np.asarray(q, dtype=float)
        self._s_list = self.s.tolist()
        self.q_start = self.q_samples[0].copy()
        self.q_end = self.q_samples[-1].copy()
        self.length = float(self.s[-1])
        ds = np.diff(self.s)
        self.slopes = np.diff(self.q_samples, axis=0) / ds[:, None] if len(ds) else np.zeros((0, 6))

    def _cell(self, s: float) -> int:
        return max(0, min(len(self._s_list) - 2, bisect.bisect_right(self._s_list, s) - 1))

    def q(self, s: float) -> np.ndarray:
        if len(self._s_list) < 2:
            return self.q_start.copy()
        k = self._cell(s)
        return self.q_samples[k] + self.slopes[k] * (s - self._s_list[k])

    def derivatives(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if len(self._s_list) < 2:
            zero = np.zeros_like(self.q_start)
            return self.q_start.copy(), zero, zero
        k = self._cell(s)
        q = self.q_samples[k] + self.slopes[k] * (s - self._s_list[k])
        # The curvature of the underlying smooth path, from neighbouring slopes (the linear pieces have none).
        k0, k1 = max(0, k - 1), min(len(self.slopes) - 1, k + 1)
        span = 0.5 * (self._s_list[k1 + 1] + self._s_list[k1]) - 0.5 * (
            self._s_list[k0 + 1] + self._s_list[k0]
        )
        ddq = (self.slopes[k1] - self.slopes[k0]) / span if span > 0 else np.zeros_like(q)
        return q, self.slopes[k], ddq


class SplineJointPath:
    """A smooth joint-space curve through every waypoint q_0..q_n exactly (what PUT /poses/run follows).

    Cubic Hermite pieces with the three-point tangents of a non-uniform Catmull-Rom spline: the velocity
    direction is continuous at each waypoint, so the arm passes it without stopping. s is measured as in
    JointPath (a chord's length is max_i |dq_i| / vmax_i); the time scaling keeps the joints in their limits.
    """

    def __init__(self, waypoints: np.ndarray, vmax: np.ndarray) -> None:
        waypoints = np.atleast_2d(np.asarray(waypoints, dtype=float))
        keep = dedupe_waypoints(list(waypoints), lambda a, b: float(np.max(np.abs(a - b))))
        self.waypoints = waypoints[keep]
        self.q_start = self.waypoints[0].copy()
        self.q_end = self.waypoints[-1].copy()
        n = len(self.waypoints)
        if n < 2:
            self.length = 0.0
            self._knots: list[float] = [0.0]
            self.waypoint_s = [0.0] * len(waypoints)
            return
        deltas = np.diff(self.waypoints, axis=0)
        lengths = np.max(np.abs(deltas) / vmax, axis=1)
        slopes = deltas / lengths[:, None]
        tangents = np.empty_like(self.waypoints)
        tangents[0], tangents[-1] = slopes[0], slopes[-1]
        for j in range(1, n - 1):
            h0, h1 = lengths[j - 1], lengths[j]
            tangents[j] = (h1 * slopes[j - 1] + h0 * slopes[j]) / (h0 + h1)
        self._lengths = lengths
        self._tangents = tangents
        self._knots = np.concatenate([[0.0], np.cumsum(lengths)]).tolist()
        self.length = self._knots[-1]
        self.waypoint_s = waypoint_s_of(keep, self._knots, len(waypoints))

    def _segment(self, s: float) -> tuple[int, float, float]:
        j = max(0, min(len(self._knots) - 2, bisect.bisect_right(self._knots, s) - 1))
        h = float(self._lengths[j])
        return j, min(max((s - self._knots[j]) / h, 0.0), 1.0), h

    def q(self, s: float) -> np.ndarray:
        return self.derivatives(s)[0]

    def derivatives(self, s: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self.length == 0.0:
            zero = np.zeros_like(self.q_start)
            return self.q_start.copy(), zero, zero
        j, u, h = self._segment(s)
        p0, p1 = self.waypoints[j], self.waypoints[j + 1]
        m0, m1 = self._tangents[j] * h, self._tangents[j + 1] * h
        u2, u3 = u * u, u * u * u
        q = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 + (u3 - u2) * m1
        dq = (
            (6 * u2 - 6 * u) * p0 + (3 * u2 - 4 * u + 1) * m0 + (-6 * u2 + 6 * u) * p1 + (3 * u2 - 2 * u) * m1
        ) / h
        ddq = ((12 * u - 6) * p0 + (6 * u - 4) * m0 + (-12 * u + 6) * p1 + (6 * u - 2) * m1) / (h * h)
        return q, dq, ddq

    def grid(self, max_step: float) -> np.ndarray:
        return refine_grid(self._knots, max_step)
