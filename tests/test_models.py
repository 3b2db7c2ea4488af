"""The PULSE 75 and PULSE 90 models (urdf/, assets/): what the viewer, kinematics and simulator rely on."""

from __future__ import annotations

import math
import subprocess
import sys
from functools import cache
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import trimesh
import yourdfpy

from pendant.kinematics.dh import DH_TABLES
from pendant.kinematics.limits import (
    GRIPPER_STROKE_M,
    JOINT_LOWER_RAD,
    JOINT_MAX_EFFORT_NM,
    JOINT_MAX_SPEED_RAD_S,
    JOINT_UPPER_RAD,
)
from pendant.paths import MODEL_NAMES, assets_dir, data_root, urdf_path

POS_TOL_M = 1e-6
ROT_TOL = 1e-9
LIMIT_TOL = 1e-9
COVER_TOL_M = 1e-6
ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 7))
HOME_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
ZERO_DEG = (0.0,) * 6
CHECK_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)
# The PULSE 75 tcp at CHECK_DEG, worked out by hand from the DH table.
CHECK_TCP_PULSE75_M = (-0.4661, -0.1205, 0.4849)
CHECK_TCP_TOL_M = 5e-5  # the hand-worked figures have four decimals
MASS_RANGE_KG = {"pulse75": (18.0, 22.0), "pulse90": (21.0, 25.0)}
SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "build_models.py"

models = pytest.mark.parametrize("model", MODEL_NAMES)


@cache
def _urdf(model: str) -> yourdfpy.URDF:
    return yourdfpy.URDF.load(str(urdf_path(model)))


@cache
def _pinocchio(model: str) -> tuple[pin.Model, pin.GeometryModel]:
    return pin.buildModelsFromUrdf(str(urdf_path(model)), geometry_types=pin.GeometryType.COLLISION)


def _dh_tcp(model: str, q: np.ndarray) -> np.ndarray:
    """T_base_tcp by the DH product, independent of the URDF."""
    table = DH_TABLES[model]
    T = np.eye(4)
    for theta, d, a, alpha in zip(q, table.d, table.a, table.alpha, strict=True):
        ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
        T = T @ np.array(
            [[ct, -st * ca, st * sa, a * ct], [st, ct * ca, -ct * sa, a * st], [0, sa, ca, d], [0, 0, 0, 1]]
        )
    yaw = table.tcp_yaw
    return T @ np.array(
        [
            [math.cos(yaw), -math.sin(yaw), 0, 0],
            [math.sin(yaw), math.cos(yaw), 0, 0],
            [0, 0, 1, 0],
            [0, 0, 0, 1],
        ]
    )


def _urdf_tcp(model: str, q_deg: tuple[float, ...], opening: float = 0.0) -> np.ndarray:
    urdf = _urdf(model)
    urdf.update_cfg(np.concatenate([np.radians(q_deg), [opening]]))
    return urdf.get_transform("tcp", "base_link")


def trimesh_points_z(T_tcp_mesh: np.ndarray, vertices: np.ndarray) -> float:
    """How far the mesh reaches along the tcp's z axis."""
    return float((vertices @ T_tcp_mesh[:3, :3].T + T_tcp_mesh[:3, 3])[:, 2].max())


@models
def test_arm_has_six_revolute_joints_with_the_limits_of_limits_py(model: str) -> None:
    urdf = _urdf(model)
    assert urdf.actuated_joint_names == [*ARM_JOINTS, "finger_left_joint"]
    for i, name in enumerate(ARM_JOINTS):
        joint = urdf.joint_map[name]
        assert joint.type == "revolute"
        np.testing.assert_allclose(joint.axis, [0, 0, 1])
        assert joint.limit.lower == pytest.approx(JOINT_LOWER_RAD[i], abs=LIMIT_TOL)
        assert joint.limit.upper == pytest.approx(JOINT_UPPER_RAD[i], abs=LIMIT_TOL)
        assert joint.limit.velocity == pytest.approx(JOINT_MAX_SPEED_RAD_S[i], abs=LIMIT_TOL)
        assert joint.limit.effort == pytest.approx(JOINT_MAX_EFFORT_NM[i], abs=LIMIT_TOL)


def test_pulse75_check_pose_puts_the_tcp_where_the_dh_table_says() -> None:
    T = _urdf_tcp("pulse75", CHECK_DEG)
    np.testing.assert_allclose(T[:3, 3], CHECK_TCP_PULSE75_M, atol=CHECK_TCP_TOL_M)
    np.testing.assert_allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=ROT_TOL)  # Rx(pi): tool down


@models
@pytest.mark.parametrize("q_deg", [HOME_DEG, ZERO_DEG, CHECK_DEG, (10.0, -70.0, 45.0, 30.0, -60.0, 120.0)])
def test_urdf_tcp_matches_the_dh_product(model: str, q_deg: tuple[float, ...]) -> None:
    np.testing.assert_allclose(_urdf_tcp(model, q_deg), _dh_tcp(model, np.radians(q_deg)), atol=POS_TOL_M)


@models
def test_pinocchio_loads_the_model_and_its_collision_and_visual_geometry(model: str) -> None:
    pin_model, collision = _pinocchio(model)
    assert [pin_model.names[i] for i in range(1, 7)] == list(ARM_JOINTS)
    assert pin_model.nq == 8  # six arm joints and two fingers (mimic joints are separate unless mimic=True)
    collision_links = {pin_model.frames[g.parentFrame].name for g in collision.geometryObjects}
    assert {
        "base_link",
        *(f"link{i}" for i in range(1, 7)),
        "gripper_body",
        "finger_left",
        "finger_right",
    } <= collision_links
    # Visual meshes are named relative to urdf/, which pinocchio resolves through package_dirs.
    _, visual = pin.buildModelsFromUrdf(
        str(urdf_path(model)),
        package_dirs=[str(urdf_path(model).parent)],
        geometry_types=pin.GeometryType.VISUAL,
    )
    assert len(visual.geometryObjects) == 10


@models
@pytest.mark.parametrize("q_deg", [HOME_DEG, ZERO_DEG, CHECK_DEG])
@pytest.mark.parametrize("opening", [0.0, GRIPPER_STROKE_M])
def test_only_neighbouring_links_touch_in_the_standard_poses(
    model: str, q_deg: tuple[float, ...], opening: float
) -> None:
    pin_model, collision = _pinocchio(model)
    collision = collision.copy()
    collision.addAllCollisionPairs()
    data, geometry_data = pin_model.createData(), pin.GeometryData(collision)
    q = np.concatenate([np.radians(q_deg), [opening, opening]])
    pin.computeCollisions(pin_model, data, collision, geometry_data, q, False)
    parents = pin_model.parents
    touching = []
    for k, pair in enumerate(collision.collisionPairs):
        a, b = collision.geometryObjects[pair.first], collision.geometryObjects[pair.second]
        j, k_joint = a.parentJoint, b.parentJoint
        neighbours = j == k_joint or parents[j] == k_joint or parents[k_joint] == j
        if not neighbours and geometry_data.collisionResults[k].isCollision():
            touching.append((a.name, b.name))
    assert touching == []


@models
def test_total_mass_and_inertias_are_physical(model: str) -> None:
    pin_model, _ = _pinocchio(model)
    low, high = MASS_RANGE_KG[model]
    assert low <= sum(inertia.mass for inertia in pin_model.inertias) <= high
    for inertia in pin_model.inertias[1:]:
        principal = np.linalg.eigvalsh(inertia.inertia)
        assert principal.min() > 0
        assert principal.sum() - 2 * principal.max() >= -1e-12  # triangle inequality of a real body


@models
def test_every_mesh_file_the_urdf_names_exists_next_to_it(model: str) -> None:
    urdf = _urdf(model)
    filenames = [
        visual.geometry.mesh.filename
        for link in urdf.robot.links
        for visual in link.visuals
        if visual.geometry.mesh is not None
    ]
    assert len(filenames) == 10
    for filename in filenames:
        assert filename.startswith("../assets/")
        assert (urdf_path(model).parent / filename).resolve().is_file()


def _inside_collision_shapes(link: yourdfpy.Link, points: np.ndarray) -> np.ndarray:
    """Which points lie inside (within COVER_TOL_M of) one of the link's collision primitives."""
    inside = np.zeros(len(points), dtype=bool)
    for collision in link.collisions:
        T = collision.origin if collision.origin is not None else np.eye(4)
        local = (points - T[:3, 3]) @ T[:3, :3]
        if collision.geometry.cylinder is not None:
            cylinder = collision.geometry.cylinder
            radial = np.hypot(local[:, 0], local[:, 1])
            inside |= (radial <= cylinder.radius + COVER_TOL_M) & (
                np.abs(local[:, 2]) <= cylinder.length / 2 + COVER_TOL_M
            )
        else:
            half = np.asarray(collision.geometry.box.size) / 2
            inside |= np.all(np.abs(local) <= half + COVER_TOL_M, axis=1)
    return inside


@models
def test_collision_primitives_cover_every_visual_mesh(model: str) -> None:
    urdf = _urdf(model)
    for link in urdf.robot.links:
        for visual in link.visuals:
            mesh_file = (urdf_path(model).parent / visual.geometry.mesh.filename).resolve()
            mesh = trimesh.load(mesh_file, force="mesh")
            assert isinstance(mesh, trimesh.Trimesh)
            vertices = mesh.vertices
            uncovered = ~_inside_collision_shapes(link, vertices)
            assert not uncovered.any(), f"{link.name}: {vertices[uncovered][:3]} outside its collision shapes"


@models
def test_meshes_load_with_light_links_and_dark_joint_caps(model: str) -> None:
    urdf = yourdfpy.URDF.load(str(urdf_path(model)), build_scene_graph=True, load_meshes=True)
    colours = [geometry.visual.material.baseColorFactor for geometry in urdf.scene.geometry.values()]
    brightness = [int(colour[:3].mean()) for colour in colours]
    assert max(brightness) > 220  # white link tubes
    assert min(brightness) < 60  # dark caps and rings


@models
def test_gripper_fingers_open_symmetrically_beyond_the_flange(model: str) -> None:
    urdf = _urdf(model)
    assert urdf.joint_map["finger_left_joint"].type == "prismatic"
    assert urdf.joint_map["finger_left_joint"].limit.upper == pytest.approx(GRIPPER_STROKE_M)
    assert urdf.joint_map["finger_right_joint"].mimic.joint == "finger_left_joint"

    def finger_gap(opening: float) -> float:
        urdf.update_cfg(np.concatenate([np.radians(HOME_DEG), [opening]]))
        left = urdf.get_transform("finger_left", "tcp")[:3, 3]
        right = urdf.get_transform("finger_right", "tcp")[:3, 3]
        return float(np.linalg.norm(left - right))

    assert finger_gap(GRIPPER_STROKE_M) - finger_gap(0.0) == pytest.approx(
        2 * GRIPPER_STROKE_M, abs=POS_TOL_M
    )
    loaded = yourdfpy.URDF.load(str(urdf_path(model)), build_scene_graph=True, load_meshes=True)
    scene = loaded.scene
    tips = [
        trimesh_points_z(
            scene.graph.get(frame_to=node, frame_from="tcp")[0], scene.geometry[geometry].vertices
        )
        for node in scene.graph.nodes_geometry
        for geometry in [scene.graph[node][1]]
        if scene.graph.transforms.parents[node].startswith("finger_")
    ]
    assert min(tips) >= 0.08 and max(tips) <= 0.10  # the gripper reaches 8-10 cm past the flange


def test_generator_rewrites_the_committed_files_byte_for_byte(tmp_path: Path) -> None:
    subprocess.run([sys.executable, str(SCRIPT), "--out", str(tmp_path)], check=True, capture_output=True)
    committed = sorted(
        p.relative_to(data_root()) for d in (urdf_path("pulse75").parent, assets_dir()) for p in d.iterdir()
    )
    generated = sorted(p.relative_to(tmp_path) for d in ("urdf", "assets") for p in (tmp_path / d).iterdir())
    assert generated == committed
    for relative in generated:
        assert (tmp_path / relative).read_bytes() == (data_root() / relative).read_bytes(), relative


def test_assets_stay_small() -> None:
    assert sum(p.stat().st_size for p in assets_dir().iterdir()) < 3_000_000
