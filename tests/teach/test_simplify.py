"""Path simplification: a hand-drawn curve sampled at 30 Hz comes back as at most 100 waypoints whose straight
segments stay within the tolerance of every sample."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import viser.transforms as vtf

from pendant.teach.simplify import MAX_WAYPOINTS, simplify_to

RATE_HZ = 30.0


def hand_drawn(seconds: float, seed: int = 7) -> tuple[np.ndarray, vtf.SO3]:
    """A wobbly loop in mm with the tool turning slowly, as a hand would draw it."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, seconds, 1.0 / RATE_HZ)
    phase = rng.uniform(0, 2 * np.pi, 3)
    points = np.column_stack(
        [
            400 + 150 * np.cos(0.8 * t) + 20 * np.sin(3.1 * t + phase[0]),
            100 * np.sin(0.8 * t) + 15 * np.sin(2.3 * t + phase[1]),
            300 + 40 * np.sin(0.5 * t + phase[2]),
        ]
    )
    rpy = np.column_stack([np.pi + 0.2 * np.sin(0.3 * t), 0.15 * np.cos(0.4 * t), 0.5 * t / seconds])
    return points, vtf.SO3.from_rpy_radians(rpy[:, 0], rpy[:, 1], rpy[:, 2])


def polyline_errors(points: np.ndarray, rotations: vtf.SO3, kept: list[int]) -> tuple[float, float]:
    """The worst distance (mm) of a sample from the segment between the kept samples around it, and of its
    rotation (°) from the rotation interpolated there: what playing the waypoints back in lines would miss."""
    worst_mm = worst_deg = 0.0
    for a, b in itertools.pairwise(kept):
        seg = points[b] - points[a]
        for i in range(a, b + 1):
            t = float(np.clip((points[i] - points[a]) @ seg / max(seg @ seg, 1e-12), 0.0, 1.0))
            worst_mm = max(worst_mm, float(np.linalg.norm(points[a] + t * seg - points[i])))
            R_a, R_b, R_i = (vtf.SO3(rotations.wxyz[k]) for k in (a, b, i))
            between = R_a @ vtf.SO3.exp(t * (R_a.inverse() @ R_b).log())
            worst_deg = max(worst_deg, float(np.degrees(np.linalg.norm((between.inverse() @ R_i).log()))))
    return worst_mm, worst_deg


def test_a_hand_drawn_curve_keeps_within_1_mm_and_1_degree() -> None:
    points, rotations = hand_drawn(8.0)
    kept, tol_mm, tol_deg = simplify_to(points, rotations, 1.0, 1.0)
    assert (tol_mm, tol_deg) == (1.0, 1.0)
    assert kept[0] == 0 and kept[-1] == len(points) - 1
    assert 2 < len(kept) <= MAX_WAYPOINTS
    assert len(kept) < len(points) / 3  # it does simplify
    worst_mm, worst_deg = polyline_errors(points, rotations, kept)
    assert worst_mm <= 1.0 + 1e-9
    assert worst_deg <= 1.0 + 1e-9


def test_a_path_too_long_for_100_waypoints_relaxes_the_tolerance_to_fit() -> None:
    points, rotations = hand_drawn(60.0)
    kept, tol_mm, tol_deg = simplify_to(points, rotations, 0.1, 0.1)
    assert len(kept) <= MAX_WAYPOINTS
    assert tol_mm > 0.1 and tol_deg > 0.1
    worst_mm, worst_deg = polyline_errors(points, rotations, kept)
    assert worst_mm <= tol_mm + 1e-9 and worst_deg <= tol_deg + 1e-9


def test_a_straight_line_is_its_two_ends_and_bad_tolerances_are_refused() -> None:
    points = np.column_stack([np.linspace(0, 300, 90), np.zeros(90), np.full(90, 200.0)])
    rotations = vtf.SO3.from_rpy_radians(np.zeros(90), np.zeros(90), np.zeros(90))
    assert simplify_to(points, rotations)[0] == [0, 89]
    with pytest.raises(ValueError, match="more than 0"):
        simplify_to(points, rotations, 0.0, 1.0)
