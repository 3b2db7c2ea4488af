"""Time scaling of a geometric path: s(t) on [0, L] under per-cell speed and acceleration caps.

The path is cut into cells s_0 < s_1 < ... < s_N. Each cell has a cap on ds/dt, and the joint accelerations
q'' s'^2 + q' s'' must stay within the joint limits. A forward pass (accelerate as hard as allowed) and a
backward pass (brake in time for every cap and for the stop at the end) give the fastest speed at each grid
point; inside a cell the acceleration is constant. For a straight
joint move with uniform caps this is the classic trapezoidal velocity profile, and for a blended path it
slows down only where a corner or the TCP cap asks for it. Evaluating s(t) is a bisection plus a quadratic.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class TimeScaling:
    """s(t), ds/dt, d2s/dt2 of one motion, starting and ending at rest."""

    s: list[float]  # grid points, N + 1
    v: list[float]  # ds/dt at the grid points
    a: list[float]  # d2s/dt2 in each cell, N
    t: list[float]  # time at the grid points, t[0] = 0

    @property
    def duration(self) -> float:
        return self.t[-1]

    @property
    def length(self) -> float:
        return self.s[-1]

    def at(self, t: float) -> tuple[float, float, float]:
        """(s, ds/dt, d2s/dt2) at time t after the start (clamped to the ends)."""
        if t <= 0.0 or len(self.t) < 2:
            return self.s[0], 0.0, 0.0
        if t >= self.t[-1]:
            return self.s[-1], 0.0, 0.0
        k = bisect.bisect_right(self.t, t) - 1
        tau = t - self.t[k]
        v0 = self.v[k]
        acc = self.a[k]
        s = self.s[k] + v0 * tau + 0.5 * acc * tau * tau
        # Never overshoot the cell through rounding.
        s = min(s, self.s[k + 1])
        return s, v0 + acc * tau, acc


def still(length: float = 0.0) -> TimeScaling:
    """A motion of zero duration (the target is where the arm already is)."""
    return TimeScaling(s=[length], v=[0.0], a=[], t=[0.0])


def plan(
    s_grid: np.ndarray,
    v_cap: np.ndarray,
    dq_ds: np.ndarray,
    ddq_ds2: np.ndarray,
    accel_limit: np.ndarray,
) -> TimeScaling:
    """The fastest rest-to-rest s(t) along `s_grid` (N + 1,).

    Per cell k: `v_cap[k]` caps ds/dt; the joint accelerations q'' s'^2 + q' s'' (with the cell's
    `dq_ds[k]`, `ddq_ds2[k]`, shape (N, n_joints)) must stay within +-`accel_limit` (n_joints,). The caller
    makes v_cap respect |q''| s'^2 <= accel_limit, so that cruising is always allowed.
    """
    s = np.asarray(s_grid, dtype=float)
    n_cells = len(s) - 1
    if n_cells < 1 or s[-1] - s[0] <= 0.0:
        return still(float(s[-1]) if len(s) else 0.0)
    v_cap = np.asarray(v_cap, dtype=float)
    dq_ds = np.asarray(dq_ds, dtype=float)
    ddq_ds2 = np.asarray(ddq_ds2, dtype=float)
    if n_cells == 1:  # a single cell would have to start and end at rest: split it
        s = np.array([s[0], 0.5 * (s[0] + s[1]), s[1]])
        v_cap, dq_ds, ddq_ds2, n_cells = (
            np.repeat(v_cap, 2),
            np.repeat(dq_ds, 2, 0),
            np.repeat(ddq_ds2, 2, 0),
            2,
        )
    if v_cap.shape != (n_cells,) or dq_ds.shape[0] != n_cells or ddq_ds2.shape != dq_ds.shape:
        raise ValueError("v_cap, dq_ds and ddq_ds2 need one entry per cell")
    if np.any(v_cap <= 0.0) or np.any(np.asarray(accel_limit) <= 0.0):
        raise ValueError("speed and acceleration caps must be positive")
    limits = [float(a) for a in accel_limit]
    d1 = dq_ds.tolist()
    d2 = ddq_ds2.tolist()

    def accel_range(k: int, v: float) -> tuple[float, float]:
        """The (most negative, most positive) s'' the joints allow in cell k at speed v."""
        lo, hi = -math.inf, math.inf
        v2 = v * v
        for q1, q2, limit in zip(d1[k], d2[k], limits, strict=True):
            if abs(q1) < 1e-12:
                continue
            centripetal = q2 * v2
            a = (-limit - centripetal) / q1
            b = (limit - centripetal) / q1
            if a > b:
                a, b = b, a
            lo = max(lo, a)
            hi = min(hi, b)
        return min(lo, 0.0), max(hi, 0.0)

    ds_list = np.diff(s).tolist()
    v = [0.0, *np.minimum(v_cap[:-1], v_cap[1:]).tolist(), 0.0]
    for k in range(n_cells):  # forward: accelerate as hard as the joints allow
        hi = accel_range(k, v[k])[1]
        v[k + 1] = min(v[k + 1], math.sqrt(v[k] * v[k] + 2.0 * hi * ds_list[k]))
    for k in range(n_cells - 1, -1, -1):  # backward: brake in time for every cap and for the stop
        lo = accel_range(k, v[k + 1])[0]
        v[k] = min(v[k], math.sqrt(v[k + 1] * v[k + 1] - 2.0 * lo * ds_list[k]))
    acc: list[float] = []
    times = [0.0]
    for k in range(n_cells):
        v0, v1, d = v[k], v[k + 1], ds_list[k]
        acc.append((v1 * v1 - v0 * v0) / (2.0 * d))
        times.append(times[-1] + 2.0 * d / (v0 + v1))
    return TimeScaling(s=s.tolist(), v=v, a=acc, t=times)
