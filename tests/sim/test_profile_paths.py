"""The time scaling and the blended paths on their own, without an arm."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.kinematics.transforms import rotvec_to_matrix
from pendant.sim import profile
from pendant.sim.paths import (
    CARTESIAN_BLEND_TOL_M,
    JOINT_BLEND_TOL_RAD,
    CartesianPath,
    JointPath,
)

TOL = 1e-9


def _plan(grid: np.ndarray, v_cap: np.ndarray, a_max: float) -> profile.TimeScaling:
    """A one-joint straight path (q = s) under a speed cap per cell and an acceleration limit."""
    n = len(grid) - 1
    return profile.plan(grid, v_cap, np.ones((n, 1)), np.zeros((n, 1)), np.array([a_max]))


def _samples(scaling: profile.TimeScaling, n: int = 4001) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ts = np.linspace(0.0, scaling.duration, n)
    values = np.array([scaling.at(t) for t in ts])
    return ts, values[:, 0], values[:, 1]


def test_uniform_caps_give_a_trapezoid_from_rest_to_rest() -> None:
    length, v_max, a_max = 2.0, 0.5, 1.0
    grid = np.linspace(0.0, length, 401)
    scaling = _plan(grid, np.full(400, v_max), a_max)
    _, s, v = _samples(scaling)
    assert s[0] == 0.0 and s[-1] == pytest.approx(length, abs=TOL)
    assert v[0] == 0.0 and v[-1] == 0.0
    assert np.max(v) <= v_max + TOL
    assert np.all(np.abs(scaling.a) <= a_max + TOL)
    # The classic trapezoid: L / v + v / a (to within one cell of rounding the corners).
    assert scaling.duration == pytest.approx(length / v_max + v_max / a_max, rel=2e-3)


def test_short_move_is_a_triangle() -> None:
    length, a_max = 0.01, 2.0
    scaling = _plan(np.linspace(0.0, length, 101), np.full(100, 10.0), a_max)
    assert scaling.duration == pytest.approx(2.0 * math.sqrt(length / a_max), rel=1e-6)


def test_a_slow_cell_slows_only_around_it() -> None:
    grid = np.linspace(0.0, 10.0, 1001)
    v_cap = np.full(1000, 1.0)
    v_cap[500] = 0.2
    scaling = _plan(grid, v_cap, 1.0)
    assert scaling.at(scaling.duration / 4)[1] == pytest.approx(1.0)
    speeds = [scaling.at(t)[1] for t in np.linspace(0, scaling.duration, 5001)]
    assert min(v for v in speeds[100:-100]) == pytest.approx(0.2, abs=0.01)


def test_curvature_limits_the_speed_through_a_bend() -> None:
    # q'' = 4 per unit s^2 with a limit of 1: cruising through the cell needs s' <= 0.5.
    grid = np.linspace(0.0, 4.0, 401)
    d2 = np.zeros((400, 1))
    d2[200] = 4.0
    v_cap = np.full(400, 10.0)
    v_cap[200] = 0.5
    scaling = profile.plan(grid, v_cap, np.ones((400, 1)), d2, np.array([1.0]))
    k = 200
    assert max(scaling.v[k], scaling.v[k + 1]) <= 0.5 + 1e-12


def test_zero_length_takes_no_time() -> None:
    assert _plan(np.array([0.0, 0.0]), np.ones(1), 1.0).duration == 0.0


def test_joint_path_blends_pass_waypoints_within_tolerance_and_end_exactly() -> None:
    vmax = np.radians([120.0, 120.0, 150.0, 180.0, 180.0, 180.0])
    waypoints = np.radians(
        [[0, 0, 0, 0, 0, 0], [40, 10, -20, 0, 30, 0], [0, 50, 0, 30, 0, 10], [10, 0, 0, 0, 0, 0]]
    )
    path = JointPath(waypoints, vmax)
    s = np.linspace(0.0, path.length, 20001)
    qs = np.array([path.q(x) for x in s])
    assert np.allclose(qs[0], waypoints[0], atol=TOL)
    assert np.allclose(qs[-1], waypoints[-1], atol=TOL)
    for waypoint in waypoints[1:-1]:
        nearest = np.min(np.max(np.abs(qs - waypoint), axis=1))
        assert nearest <= JOINT_BLEND_TOL_RAD + 1e-6
    # The tangent is continuous: no corner anywhere.
    tangents = np.diff(qs, axis=0) / np.diff(s)[:, None]
    assert np.max(np.abs(np.diff(tangents, axis=0))) < 0.05


def test_cartesian_path_is_straight_between_blends_and_slerps_orientation() -> None:
    T0, T1, T2 = np.eye(4), np.eye(4), np.eye(4)
    T1[:3, 3] = (0.3, 0.0, 0.0)
    T1[:3, :3] = rotvec_to_matrix(np.array([0.0, 0.0, 0.6]))
    T2[:3, 3] = (0.3, 0.2, 0.0)
    path = CartesianPath([T0, T1, T2])
    s = np.linspace(0.0, path.length, 5001)
    poses = [path.pose(x) for x in s]
    points = np.array([T[:3, 3] for T in poses])
    assert np.allclose(poses[-1], T2, atol=TOL)
    assert np.min(np.linalg.norm(points - T1[:3, 3], axis=1)) <= CARTESIAN_BLEND_TOL_M + 1e-6
    # On the first leg (away from the blend) y stays 0 and the turn grows in proportion to x.
    first = points[:, 0] < 0.25
    assert np.max(np.abs(points[first, 1])) < TOL
    angles = np.array([np.arctan2(T[1, 0], T[0, 0]) for T in np.array(poses)[first]])
    assert np.allclose(angles, 0.6 * points[first, 0] / 0.3, atol=1e-9)
