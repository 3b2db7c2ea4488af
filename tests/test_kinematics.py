"""Closed-form FK and IK of the PULSE arms (no URDF needed)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.kinematics import ArmModel
from pendant.kinematics.dh import DH_TABLES

POS_TOL_M = 1e-6
ROT_TOL_RAD = 1e-6
# The stretched elbow is ill-conditioned: a 1e-16 rounding of the reach moves q3 by ~1e-8 rad.
JOINT_TOL_RAD = 1e-6
CHECK_POSE_TOL_M = 5e-5  # the published check pose is given to 0.1 mm
MODELS = sorted(DH_TABLES)
HOME_DEG = [0.0, -90.0, 0.0, -90.0, -90.0, 0.0]

# Configurations at or next to each singularity, in degrees (q5 given in radians below where tiny).
SINGULAR_DEG = {
    "wrist q5=0": [10.0, -70.0, 80.0, -30.0, 0.0, 25.0],
    "wrist q5=180": [10.0, -70.0, 80.0, -30.0, 180.0, 25.0],
    "wrist q5=-180": [-40.0, -100.0, 60.0, 10.0, -180.0, -70.0],
    "elbow stretched q3=0": [30.0, -60.0, 0.0, -45.0, -90.0, 10.0],
    "elbow folded q3=180": [30.0, -60.0, 180.0, -45.0, -60.0, 10.0],
    "home (stretched up, shoulder singular)": HOME_DEG,
    # Upper arm and forearm vertical, q4 = 90: the wrist centre lies in the plane of the J1 and J2 axes.
    "shoulder singular": [0.0, -90.0, 0.0, 90.0, -90.0, 0.0],
    "shoulder + wrist singular": [15.0, -90.0, 0.0, 90.0, 0.0, 40.0],
    "all three": [0.0, -90.0, 0.0, 90.0, 180.0, 0.0],
}


@pytest.fixture(scope="module", params=MODELS)
def arm(request: pytest.FixtureRequest) -> ArmModel:
    return ArmModel.load(request.param)


def rotation_error(R_a: np.ndarray, R_b: np.ndarray) -> float:
    R = R_a.T @ R_b
    skew = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.arctan2(0.5 * np.linalg.norm(skew), 0.5 * (np.trace(R) - 1.0)))


def assert_reaches(arm: ArmModel, q: np.ndarray, T: np.ndarray) -> None:
    assert np.all(np.isfinite(q))
    T_reached = arm.fk(q)
    assert np.linalg.norm(T_reached[:3, 3] - T[:3, 3]) < POS_TOL_M
    assert rotation_error(T_reached[:3, :3], T[:3, :3]) < ROT_TOL_RAD


def angle_difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a - b wrapped into [-pi, pi)."""
    return (np.asarray(a) - np.asarray(b) + math.pi) % (2.0 * math.pi) - math.pi


def random_configurations(arm: ArmModel, count: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(arm.lower, arm.upper, size=(count, 6))


def singular_configuration(degrees: list[float]) -> np.ndarray:
    return np.radians(degrees)


# --- FK -------------------------------------------------------------------------------------------


def test_check_pose_of_pulse75_matches_the_manual() -> None:
    arm = ArmModel.load("pulse75")
    T = arm.fk(np.radians([0.0, -90.0, 90.0, -90.0, -90.0, 0.0]))
    np.testing.assert_allclose(T[:3, 3], [-0.4661, -0.1205, 0.4849], atol=CHECK_POSE_TOL_M)
    roll_pi = np.diag([1.0, -1.0, -1.0])
    assert rotation_error(T[:3, :3], roll_pi) < ROT_TOL_RAD


def test_closed_form_fk_equals_the_generic_dh_product(arm: ArmModel) -> None:
    for q in random_configurations(arm, 200, seed=1):
        np.testing.assert_allclose(arm.fk(q), arm.dh_frames(q)[-1], atol=1e-12)


def test_fk_returns_a_proper_transform(arm: ArmModel) -> None:
    T = arm.fk(random_configurations(arm, 1, seed=2)[0])
    assert T.shape == (4, 4)
    np.testing.assert_allclose(T[3], [0.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3), atol=1e-12)
    assert np.linalg.det(T[:3, :3]) == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("call", "argument"),
    [("fk", np.zeros(5)), ("fk", np.zeros((6, 1))), ("ik_all", np.eye(3)), ("fk", [0, 0, 0, 0, 0, math.nan])],
)
def test_wrong_shapes_and_nan_are_rejected_clearly(call: str, argument: object) -> None:
    arm = ArmModel.load("pulse75")
    with pytest.raises(ValueError, match=r"shape|finite"):
        getattr(arm, call)(argument)


def test_ik_rejects_a_wrong_q_near_shape() -> None:
    arm = ArmModel.load("pulse75")
    with pytest.raises(ValueError, match="shape"):
        arm.ik(arm.fk(np.zeros(6)), np.zeros(7))


def test_unknown_model_name_is_rejected() -> None:
    with pytest.raises(FileNotFoundError, match="unknown arm model"):
        ArmModel.load("pulse99")


# --- IK: random configurations ------------------------------------------------------------------------


def test_every_ik_branch_reaches_the_target_and_the_original_is_among_them(arm: ArmModel) -> None:
    for q in random_configurations(arm, 300, seed=3):
        T = arm.fk(q)
        solutions = arm.ik_all(T)
        assert 1 <= len(solutions) <= 8
        for solution in solutions:
            assert_reaches(arm, solution, T)
            assert arm.within_limits(solution)
        closest = np.min(np.max(np.abs(angle_difference(solutions, q)), axis=1))
        assert closest < JOINT_TOL_RAD


def test_ik_all_branches_are_distinct(arm: ArmModel) -> None:
    for q in random_configurations(arm, 50, seed=4):
        solutions = arm.ik_all(arm.fk(q))
        for i in range(len(solutions)):
            for j in range(i + 1, len(solutions)):
                assert np.max(np.abs(angle_difference(solutions[i], solutions[j]))) > 1e-6


def test_a_generic_pose_has_all_eight_branches(arm: ArmModel) -> None:
    # Wrist centre well inside the workspace, so both wrist flips are reachable with either elbow.
    q = np.radians([10.0, -60.0, 60.0, 20.0, -90.0, -70.0])
    solutions = arm.ik_all(arm.fk(q))
    assert len(solutions) == 8


def test_ik_near_a_configuration_returns_that_configuration(arm: ArmModel) -> None:
    for q in random_configurations(arm, 300, seed=5):
        answer = arm.ik(arm.fk(q), q)
        assert answer is not None
        np.testing.assert_allclose(answer, q, atol=JOINT_TOL_RAD)


def test_ik_picks_the_2pi_equivalent_nearest_q_near_within_limits(arm: ArmModel) -> None:
    q = np.radians([170.0, -80.0, 70.0, -60.0, -90.0, 300.0])
    T = arm.fk(q)
    answer = arm.ik(T, q - np.radians([0.0, 0.0, 0.0, 0.0, 0.0, 350.0]))
    assert answer is not None
    # Joint 6 can go to 300 deg or -60 deg: -60 is nearer to q_near's -50 deg.
    assert math.degrees(answer[5]) == pytest.approx(-60.0)
    np.testing.assert_allclose(answer[:5], q[:5], atol=JOINT_TOL_RAD)


def test_ik_all_gives_each_joint_in_the_limits(arm: ArmModel) -> None:
    for q in random_configurations(arm, 100, seed=6):
        solutions = arm.ik_all(arm.fk(q))
        assert np.all(solutions >= arm.lower) and np.all(solutions <= arm.upper)


# --- IK: singularities --------------------------------------------------------------------------------


@pytest.mark.parametrize("label", sorted(SINGULAR_DEG))
def test_singular_configurations_round_trip_without_nan(arm: ArmModel, label: str) -> None:
    q = singular_configuration(SINGULAR_DEG[label])
    T = arm.fk(q)
    solutions = arm.ik_all(T, q_near=q)
    assert len(solutions) >= 1
    assert not np.any(np.isnan(solutions))
    for solution in solutions:
        assert_reaches(arm, solution, T)
    answer = arm.ik(T, q)
    assert answer is not None
    np.testing.assert_allclose(answer, q, atol=JOINT_TOL_RAD)


@pytest.mark.parametrize("q5", [0.0, 1e-15, 1e-12, 1e-9, -1e-9, 1e-8, 1e-7, 1e-6, math.pi, math.pi - 1e-10])
def test_near_wrist_singularity_round_trips(arm: ArmModel, q5: float) -> None:
    for q in random_configurations(arm, 30, seed=7):
        q[4] = q5
        T = arm.fk(q)
        answer = arm.ik(T, q)
        assert answer is not None
        assert_reaches(arm, answer, T)
        # Only q4 + q6 (or q4 - q6) is defined there; the rest must come back exactly.
        np.testing.assert_allclose(answer[[0, 1, 2, 4]], q[[0, 1, 2, 4]], atol=JOINT_TOL_RAD)
        # From far away too: q6 = q_near's may put joint 4 out of reach, and IK must move along the
        # self-motion (q2, q3, q4, q6 about parallel axes) instead of giving up.
        from_far = arm.ik(T, np.zeros(6))
        assert from_far is not None
        assert_reaches(arm, from_far, T)
        solutions = arm.ik_all(T)
        assert len(solutions) >= 1
        for solution in solutions:
            assert_reaches(arm, solution, T)


def test_in_a_wrist_singularity_q6_stays_at_q_near(arm: ArmModel) -> None:
    q = singular_configuration([10.0, -70.0, 80.0, -30.0, 0.0, 25.0])
    q_near = q.copy()
    q_near[5] = math.radians(-100.0)
    answer = arm.ik(arm.fk(q), q_near)
    assert answer is not None
    assert answer[5] == pytest.approx(q_near[5])
    assert_reaches(arm, answer, arm.fk(q))


@pytest.mark.parametrize("q3", [0.0, 1e-12, 1e-9, -1e-7, math.pi, math.pi - 1e-9])
def test_near_elbow_singularity_round_trips(arm: ArmModel, q3: float) -> None:
    for q in random_configurations(arm, 30, seed=8):
        q[2] = q3
        T = arm.fk(q)
        answer = arm.ik(T, q)
        assert answer is not None
        assert_reaches(arm, answer, T)
        assert arm.ik_all(T).shape[0] >= 1


def test_near_shoulder_singularity_round_trips(arm: ArmModel) -> None:
    # Wrist centre in the plane of the J1 and J2 axes: its x1 coordinate a2 c2 + a3 c23 + d5 s234 is 0.
    a2, a3, d5 = arm.table.a[1], arm.table.a[2], arm.table.d[4]
    rng = np.random.default_rng(9)
    for _ in range(60):
        q = rng.uniform(-math.pi, math.pi, size=6)
        q234 = q[1] + q[2] + q[3]
        reach = a2 * math.cos(q[1]) + d5 * math.sin(q234)
        if abs(reach / a3) > 1.0:
            continue
        for q23 in (math.acos(-reach / a3), -math.acos(-reach / a3)):
            q[2] = q23 - q[1]
            q[3] = q234 - q23
            for offset in (0.0, 1e-12, 1e-9, -1e-9):
                q_shifted = q + np.array([0.0, offset, 0.0, 0.0, 0.0, 0.0])
                T = arm.fk(q_shifted)
                answer = arm.ik(T, q_shifted)
                assert answer is not None
                assert_reaches(arm, answer, T)


# --- unreachable and out-of-limit targets ---------------------------------------------------------------


@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (-0.6, 0.8, 0.0)])
def test_targets_out_of_reach_are_unreachable(arm: ArmModel, direction: tuple[float, float, float]) -> None:
    T = np.eye(4)
    T[:3, 3] = 2.0 * np.array(direction)
    assert arm.ik(T, np.zeros(6)) is None
    assert arm.ik_all(T).shape == (0, 6)


def test_the_base_axis_itself_is_unreachable_for_the_wrist_centre(arm: ArmModel) -> None:
    # The wrist centre can never come nearer the J1 axis than d4 (the shoulder offset).
    T = np.eye(4)
    T[:3, 3] = [0.0, 0.0, 0.5 + arm.table.d[5]]
    assert arm.ik(T, np.zeros(6)) is None


def test_ik_respects_limits_that_exclude_every_branch() -> None:
    table = DH_TABLES["pulse75"]
    lower = np.radians([-10.0, -180.0, -170.0, -360.0, -360.0, -360.0])
    upper = np.radians([10.0, 0.0, 170.0, 360.0, 360.0, 360.0])
    arm = ArmModel(table, lower=lower, upper=upper)
    behind = np.radians([180.0, -80.0, 70.0, -60.0, -90.0, 10.0])
    full_range_solutions = ArmModel(table).ik_all(arm.fk(behind))
    assert len(full_range_solutions) > 0
    # Every branch needs q1 near 180 deg or q1 near 180 - 2 asin(d4 / r): far outside +-10 deg.
    assert not (np.abs(angle_difference(full_range_solutions[:, 0], np.zeros(1))) <= math.radians(10.0)).any()
    assert arm.ik(arm.fk(behind), np.zeros(6)) is None
    assert arm.ik_all(arm.fk(behind)).shape == (0, 6)
