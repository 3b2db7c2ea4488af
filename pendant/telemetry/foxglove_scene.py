"""Foxglove's own schemas for what a recording draws: the arm's link frames (foxglove.FrameTransforms), the
links' meshes and the cell's obstacles (foxglove.SceneUpdate), the TCP's course (a line) and the event log
(foxglove.Log). Metres and radians, the arm's base frame as "base"."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pinocchio as pin
from foxglove.messages import (
    Color,
    CubePrimitive,
    CylinderPrimitive,
    FrameTransform,
    FrameTransforms,
    LinePrimitive,
    Log,
    LogLevel,
    ModelPrimitive,
    Point3,
    Pose,
    Quaternion,
    SceneEntity,
    SceneUpdate,
    SpherePrimitive,
    Timestamp,
    TriangleListPrimitive,
    Vector3,
)

from pendant.controller.cell_types import BoxObstacle, CapsuleObstacle, Obstacle, PlaneObstacle
from pendant.eventlog import Event, EventKind
from pendant.kinematics.transforms import position_to_matrix
from pendant.telemetry.arm_scene import LinkMesh

BASE_FRAME = "base"
OBSTACLE_COLOR = Color(r=0.85, g=0.45, b=0.1, a=0.6)
PATH_COLOR = Color(r=0.1, g=0.6, b=1.0, a=1.0)
PLANE_HALF_SIZE_M = 1.0  # a plane is drawn as a 2 m square around its points
_LOG_LEVELS = {EventKind.ERROR: LogLevel.Error, EventKind.REFUSED: LogLevel.Warning}


def timestamp(time_ns: int) -> Timestamp:
    return Timestamp(sec=time_ns // 1_000_000_000, nsec=time_ns % 1_000_000_000)


def _parts(T: np.ndarray) -> tuple[Vector3, Quaternion]:
    x, y, z, w = pin.Quaternion(np.asarray(T[:3, :3], dtype=float)).coeffs()
    t = T[:3, 3]
    return (
        Vector3(x=float(t[0]), y=float(t[1]), z=float(t[2])),
        Quaternion(x=float(x), y=float(y), z=float(z), w=float(w)),
    )


def pose(T: np.ndarray) -> Pose:
    position, orientation = _parts(T)
    return Pose(position=position, orientation=orientation)


def frame_transforms(time_ns: int, link_poses: dict[str, np.ndarray]) -> FrameTransforms:
    """Each link's pose in the base frame (a flat tree: base -> every link)."""
    stamp = timestamp(time_ns)
    transforms = []
    for link, T in link_poses.items():
        translation, rotation = _parts(T)
        transforms.append(
            FrameTransform(
                timestamp=stamp,
                parent_frame_id=BASE_FRAME,
                child_frame_id=link,
                translation=translation,
                rotation=rotation,
            )
        )
    return FrameTransforms(transforms=transforms)


def arm_meshes(time_ns: int, meshes: Sequence[LinkMesh]) -> SceneUpdate:
    """One entity per link, locked to the link's frame: Foxglove moves them with /tf."""
    stamp = timestamp(time_ns)
    return SceneUpdate(
        entities=[
            SceneEntity(
                timestamp=stamp,
                frame_id=mesh.link,
                id=f"arm/{mesh.link}",
                frame_locked=True,
                models=[
                    ModelPrimitive(
                        pose=pose(mesh.T_link_visual), media_type="model/gltf-binary", data=mesh.mesh
                    )
                ],
            )
            for mesh in meshes
        ]
    )


def cell(time_ns: int, obstacles: Sequence[Obstacle]) -> SceneUpdate:
    """The cell's obstacles in the base frame (a new update replaces the entities of the same id)."""
    stamp = timestamp(time_ns)
    entities = []
    for obstacle in obstacles:
        cubes: list[CubePrimitive] = []
        cylinders: list[CylinderPrimitive] = []
        spheres: list[SpherePrimitive] = []
        triangles: list[TriangleListPrimitive] = []
        if isinstance(obstacle, BoxObstacle):
            s = obstacle.sides
            T = position_to_matrix(obstacle.centerPosition)
            cubes.append(CubePrimitive(pose=pose(T), size=Vector3(x=s.x, y=s.y, z=s.z), color=OBSTACLE_COLOR))
        elif isinstance(obstacle, CapsuleObstacle):
            cylinder, ends = _capsule(obstacle)
            cylinders.append(cylinder)
            spheres.extend(ends)
        elif isinstance(obstacle, PlaneObstacle):
            triangles.append(_plane(obstacle))
        entities.append(
            SceneEntity(
                timestamp=stamp,
                frame_id=BASE_FRAME,
                id=f"cell/{obstacle.name}",
                frame_locked=True,
                cubes=cubes,
                cylinders=cylinders,
                spheres=spheres,
                triangles=triangles,
            )
        )
    return SceneUpdate(entities=entities)


def _capsule(obstacle: CapsuleObstacle) -> tuple[CylinderPrimitive, list[SpherePrimitive]]:
    a = np.array([obstacle.begin.x, obstacle.begin.y, obstacle.begin.z])
    b = np.array([obstacle.finish.x, obstacle.finish.y, obstacle.finish.z])
    d = 2.0 * obstacle.radius
    axis = b - a
    length = float(np.linalg.norm(axis))
    T = np.eye(4)
    T[:3, 3] = (a + b) / 2.0
    if length > 1e-9:  # the cylinder's own axis is z
        T[:3, :3] = pin.Quaternion.FromTwoVectors(np.array([0.0, 0.0, 1.0]), axis / length).matrix()
    ends = []
    for end in (a, b):
        T_end = np.eye(4)
        T_end[:3, 3] = end
        ends.append(SpherePrimitive(pose=pose(T_end), size=Vector3(x=d, y=d, z=d), color=OBSTACLE_COLOR))
    cylinder = CylinderPrimitive(pose=pose(T), size=Vector3(x=d, y=d, z=length), color=OBSTACLE_COLOR)
    return cylinder, ends


def _plane(obstacle: PlaneObstacle) -> TriangleListPrimitive:
    p = [np.array([q.x, q.y, q.z]) for q in obstacle.points[:3]]
    centre = sum(p) / 3.0
    u = p[1] - p[0]
    u /= max(float(np.linalg.norm(u)), 1e-9)
    normal = np.cross(p[1] - p[0], p[2] - p[0])
    v = np.cross(normal, u)
    v /= max(float(np.linalg.norm(v)), 1e-9)
    h = PLANE_HALF_SIZE_M
    corners = [centre + h * (su * u + sv * v) for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    points = [Point3(x=float(c[0]), y=float(c[1]), z=float(c[2])) for c in corners]
    return TriangleListPrimitive(points=[points[i] for i in (0, 1, 2, 0, 2, 3)], color=OBSTACLE_COLOR)


def tcp_path(time_ns: int, piece: int, points: Sequence[tuple[float, float, float]]) -> SceneUpdate:
    """A piece of the TCP's course (kept: pieces accumulate into the whole path)."""
    line = LinePrimitive(
        thickness=0.004,
        points=[Point3(x=x, y=y, z=z) for x, y, z in points],
        color=PATH_COLOR,
    )
    entity = SceneEntity(
        timestamp=timestamp(time_ns),
        frame_id=BASE_FRAME,
        id=f"tcp-path/{piece}",
        frame_locked=True,
        lines=[line],
    )
    return SceneUpdate(entities=[entity])


def log(event: Event) -> Log:
    return Log(
        timestamp=timestamp(int(event.wall_time * 1e9)),
        level=_LOG_LEVELS.get(event.kind, LogLevel.Info),
        message=f"[{event.kind.value}] {event.message}",
        name=event.source,
    )
