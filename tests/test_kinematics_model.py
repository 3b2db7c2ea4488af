"""ArmModel against its URDF: FK through yourdfpy and pinocchio, Jacobian, gravity, dynamics, collision."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yourdfpy

from pendant.kinematics import ArmModel
from pendant.kinematics.dh import DH_TABLES
from pendant.paths import urdf_path

FK_AGREEMENT_TOL_M = 1e-9
JACOBIAN_FD_TOL = 1e-6
FD_STEP_RAD = 1e-6
TORQUE_TOL_NM = 1e-9
MODELS = sorted(DH_TABLES)
ARM_JOINTS = [f"joint{i}" for i in range(1, 7)]

HOME = np.radians([0.0, -90.0, 0.0, -90.0, -90.0, 0.0])
CHECK_POSE = np.radians([0.0, -90.0, 90.0, -90.0, -90.0, 0.0])
# Upper arm and forearm stretched out horizontally, the wrist hanging down.
STRETCHED_HORIZONTAL = np.radians([0.0, 0.0, 0.0, -90.0, -90.0, 0.0])


@pytest.fixture(scope="module", params=MODELS)
def arm(request: pytest.FixtureRequest) -> ArmModel:
    return ArmModel.load(request.param)


@pytest.fixture(scope="module")
def urdf(arm: ArmModel) -> yourdfpy.URDF:
    return yourdfpy.URDF.load(
        str(arm.urdf_path), load_meshes=False, build_collision_scene_graph=False, load_collision_meshes=False
    )


def random_configurations(arm: ArmModel, count: int, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(arm.lower, arm.upper, size=(count, 6))


def finite_difference_jacobian(arm: ArmModel, q: np.ndarray) -> np.ndarray:
    J = np.zeros((6, 6))
    R = arm.fk(q)[:3, :3]
    for joint in range(6):
        step = np.zeros(6)
        step[joint] = FD_STEP_RAD
        T_plus, T_minus = arm.fk(q + step), arm.fk(q - step)
        J[:3, joint] = (T_plus[:3, 3] - T_minus[:3, 3]) / (2 * FD_STEP_RAD)
        omega_hat = (T_plus[:3, :3] - T_minus[:3, :3]) / (2 * FD_STEP_RAD) @ R.T
        J[3:, joint] = [omega_hat[2, 1], omega_hat[0, 2], omega_hat[1, 0]]
    return J


# --- the URDF and the DH table describe the same arm -----------------------------------------------------


def test_fk_agrees_across_dh_yourdfpy_and_pinocchio(arm: ArmModel, urdf: yourdfpy.URDF) -> None:
    for q in random_configurations(arm, 100, seed=11):
        T_dh = arm.fk(q)
        urdf.update_cfg(dict(zip(ARM_JOINTS, q, strict=True)))
        T_yourdfpy = urdf.get_transform("tcp", "base_link")
        T_pinocchio = arm.fk_all_links(q)["tcp"]
        np.testing.assert_allclose(T_yourdfpy, T_dh, atol=FK_AGREEMENT_TOL_M)
        np.testing.assert_allclose(T_pinocchio, T_dh, atol=FK_AGREEMENT_TOL_M)


def test_urdf_joint_limits_are_the_models_limits(arm: ArmModel, urdf: yourdfpy.URDF) -> None:
    for index, name in enumerate(ARM_JOINTS):
        limit = urdf.joint_map[name].limit
        assert limit.lower == pytest.approx(arm.lower[index], abs=1e-9)
        assert limit.upper == pytest.approx(arm.upper[index], abs=1e-9)


def test_fk_all_links_places_every_link(arm: ArmModel) -> None:
    frames = arm.fk_all_links(HOME)
    expected = {"base_link", "link1", "link2", "link3", "link4", "link5", "link6", "tcp", "gripper_body"}
    assert expected <= set(frames)
    np.testing.assert_allclose(frames["base_link"], np.eye(4), atol=1e-12)
    for T in frames.values():
        assert T.shape == (4, 4)


def test_load_accepts_a_urdf_path(arm: ArmModel) -> None:
    same = ArmModel.load(str(urdf_path(arm.name)))
    assert same.name == arm.name
    np.testing.assert_allclose(same.fk(CHECK_POSE), arm.fk(CHECK_POSE))


# --- Jacobian ----------------------------------------------------------------------------------------------


def test_jacobian_matches_finite_differences_of_fk(arm: ArmModel) -> None:
    for q in random_configurations(arm, 20, seed=12):
        J = arm.jacobian(q)
        assert J.shape == (6, 6)
        np.testing.assert_allclose(J, finite_difference_jacobian(arm, q), atol=JACOBIAN_FD_TOL)


def test_jacobian_loses_rank_in_the_wrist_singularity(arm: ArmModel) -> None:
    q = np.radians([10.0, -70.0, 80.0, -30.0, 0.0, 25.0])
    singular_values = np.linalg.svd(arm.jacobian(q), compute_uv=False)
    assert singular_values[-1] < 1e-9
    assert np.linalg.svd(arm.jacobian(CHECK_POSE), compute_uv=False)[-1] > 1e-3


# --- gravity and dynamics --------------------------------------------------------------------------------


def test_gravity_never_loads_the_vertical_base_joint(arm: ArmModel) -> None:
    for q in random_configurations(arm, 50, seed=13):
        assert abs(arm.gravity_torques(q)[0]) < TORQUE_TOL_NM


def test_gravity_loads_the_shoulder_of_a_stretched_horizontal_arm(arm: ArmModel) -> None:
    tau = arm.gravity_torques(STRETCHED_HORIZONTAL)
    assert tau.shape == (6,)
    # At least the weight of the arm beyond the shoulder (~10 kg) at a quarter of its reach.
    assert abs(tau[1]) > 10.0 * 9.81 * 0.25 * (abs(arm.table.a[1]) + abs(arm.table.a[2]))
    # Mirrored about the vertical, the load mirrors too.
    mirrored = STRETCHED_HORIZONTAL.copy()
    mirrored[1] = -math.pi
    np.testing.assert_allclose(arm.gravity_torques(mirrored)[1:3], -tau[1:3], atol=1e-9)


def test_gravity_is_inverse_dynamics_at_rest(arm: ArmModel) -> None:
    for q in random_configurations(arm, 20, seed=14):
        np.testing.assert_allclose(
            arm.inverse_dynamics(q, np.zeros(6), np.zeros(6)), arm.gravity_torques(q), atol=TORQUE_TOL_NM
        )


def test_inverse_dynamics_grows_with_acceleration(arm: ArmModel) -> None:
    q = STRETCHED_HORIZONTAL
    at_rest = arm.inverse_dynamics(q, np.zeros(6), np.zeros(6))
    accelerating = arm.inverse_dynamics(q, np.zeros(6), np.array([1.0, 0.0, 0.0, 0.0, 0.0, 0.0]))
    # Spinning the base needs torque at J1 only through the arm's inertia about the vertical.
    assert accelerating[0] > 0.1
    assert at_rest[0] == pytest.approx(0.0, abs=TORQUE_TOL_NM)


def test_inverse_dynamics_checks_shapes(arm: ArmModel) -> None:
    with pytest.raises(ValueError, match="dq"):
        arm.inverse_dynamics(HOME, np.zeros(5), np.zeros(6))


# --- collision ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "q", [HOME, CHECK_POSE, STRETCHED_HORIZONTAL], ids=["home", "check pose", "horizontal"]
)
def test_ordinary_poses_are_collision_free(arm: ArmModel, q: np.ndarray) -> None:
    assert not arm.in_collision(q)
    assert arm.colliding_pairs(q) == []


@pytest.mark.parametrize("q3_deg", [170.0, -170.0])
def test_forearm_folded_into_the_upper_arm_collides(arm: ArmModel, q3_deg: float) -> None:
    q = np.radians([0.0, -90.0, q3_deg, -90.0, -90.0, 0.0])
    assert arm.in_collision(q)
    assert all("floor" not in pair for pair in arm.colliding_pairs(q))


def test_arm_leaning_into_the_floor_collides(arm: ArmModel) -> None:
    q = np.radians([0.0, 30.0, 0.0, -90.0, -90.0, 0.0])  # q2 = +30 deg tips the upper arm down
    assert arm.in_collision(q)
    assert any("floor" in pair for pair in arm.colliding_pairs(q))


def test_wrist_pointing_down_just_above_the_floor_is_free_until_it_touches(arm: ArmModel) -> None:
    # Reach down at the check pose's x, y and lower the TCP until the gripper hits the floor.
    T = arm.fk(CHECK_POSE)
    heights_free = []
    for height in (0.30, 0.20, 0.15, 0.12, 0.0, -0.02):
        T[2, 3] = height
        q = arm.ik(T, CHECK_POSE)
        assert q is not None
        heights_free.append(not arm.in_collision(q))
    assert heights_free[:3] == [True, True, True]
    assert heights_free[-2:] == [False, False]


def test_in_collision_checks_shape() -> None:
    arm = ArmModel.load("pulse75")
    with pytest.raises(ValueError, match="shape"):
        arm.in_collision(np.zeros(7))
