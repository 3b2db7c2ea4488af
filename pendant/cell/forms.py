"""Obstacles to and from the Cell tab's fields: millimetres and degrees in the page, metres and radians on the
wire. One set of fields serves the three kinds: `at` (box centre, capsule start, a point of the plane),
`rpy` (box and plane orientation: the plane is the frame's XY plane), `size` (box sides), `end` (capsule
end), `radius` (capsule)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from pydantic import TypeAdapter, ValidationError

from pendant.controller import Point, Position, Rotation
from pendant.controller.cell_types import (
    BoxObstacle,
    CapsuleObstacle,
    Obstacle,
    PlaneObstacle,
    SimplifiedCapsuleObstacle,
    ToolShape,
)
from pendant.kinematics.transforms import matrix_to_position, position_to_matrix

KINDS = ("BOX", "CAPSULE", "PLANE")
SIZE_MM_MAX = 10_000.0
Vec3 = tuple[float, float, float]
_OBSTACLE: TypeAdapter[Obstacle] = TypeAdapter(Obstacle)


def vec3(values: Sequence[float]) -> Vec3:
    """Three numbers of a vector field as floats (the field holds exactly three)."""
    x, y, z = values
    return float(x), float(y), float(z)


MM_LIMIT = 2000.0  # a tool or base offset beyond 2 m is a typing error


def position_from_form(
    xyz_mm: tuple[float, float, float], rpy_deg: tuple[float, float, float], *, limit_mm: float = MM_LIMIT
) -> Position:
    """A Position from millimetres and degrees; raises ValueError with a message the operator can act on."""
    values = (*xyz_mm, *rpy_deg)
    if not all(math.isfinite(v) for v in values):
        raise ValueError("every field must be a finite number")
    if max(abs(v) for v in xyz_mm) > limit_mm:
        raise ValueError(f"offsets must be within ±{limit_mm:.0f} mm")
    x, y, z = (v / 1000.0 for v in xyz_mm)
    roll, pitch, yaw = (math.radians(v) for v in rpy_deg)
    return Position(point=Point(x=x, y=y, z=z), rotation=Rotation(roll=roll, pitch=pitch, yaw=yaw))


@dataclass(frozen=True)
class ObstacleForm:
    kind: str
    name: str
    at_mm: Vec3 = (0.0, 0.0, 0.0)
    rpy_deg: Vec3 = (0.0, 0.0, 0.0)
    size_mm: Vec3 = (100.0, 100.0, 100.0)
    end_mm: Vec3 = (0.0, 0.0, 100.0)
    radius_mm: float = 50.0


def _point(xyz_m: np.ndarray) -> Point:
    return Point(x=float(xyz_m[0]), y=float(xyz_m[1]), z=float(xyz_m[2]))


def _mm(point: Point) -> Vec3:
    return (point.x * 1000.0, point.y * 1000.0, point.z * 1000.0)


def obstacle_from_form(form: ObstacleForm) -> Obstacle:
    """The obstacle the fields describe; ValueError with a message the operator can act on."""
    name = form.name.strip()
    if not name:
        raise ValueError("the obstacle needs a name")
    numbers = (*form.at_mm, *form.rpy_deg, *form.size_mm, *form.end_mm, form.radius_mm)
    if not all(math.isfinite(v) for v in numbers):
        raise ValueError("every field must be a finite number")
    if max(abs(v) for v in (*form.at_mm, *form.size_mm, *form.end_mm, form.radius_mm)) > SIZE_MM_MAX:
        raise ValueError(f"sizes and coordinates must be within ±{SIZE_MM_MAX:.0f} mm")
    frame = position_to_matrix(position_from_form(form.at_mm, form.rpy_deg, limit_mm=SIZE_MM_MAX))
    at = np.asarray(form.at_mm) / 1000.0
    data: dict[str, object]
    if form.kind == "BOX":
        if min(form.size_mm) <= 0.0:
            raise ValueError("a box's sides must be longer than 0 mm")
        data = {
            "obstacleType": "BOX",
            "name": name,
            "sides": _point(np.asarray(form.size_mm) / 1000.0),
            "centerPosition": matrix_to_position(frame),
        }
    elif form.kind == "CAPSULE":
        if form.radius_mm <= 0.0:
            raise ValueError("a capsule's radius must be more than 0 mm")
        data = {
            "obstacleType": "CAPSULE",
            "name": name,
            "radius": form.radius_mm / 1000.0,
            "begin": _point(at),
            "finish": _point(np.asarray(form.end_mm) / 1000.0),
        }
    elif form.kind == "PLANE":
        x_axis, y_axis = frame[:3, 0], frame[:3, 1]
        data = {
            "obstacleType": "PLANE",
            "name": name,
            "points": [_point(at), _point(at + x_axis), _point(at + y_axis)],
        }
    else:
        raise ValueError(f"the kind must be one of {', '.join(KINDS)}")
    try:
        return _OBSTACLE.validate_python(data)
    except ValidationError as error:
        raise ValueError(error.errors()[0]["msg"]) from None


def plane_frame(obstacle: PlaneObstacle) -> np.ndarray:
    """The plane as a frame: origin at its first point, x towards the second, z its normal."""
    p0, p1, p2 = (np.array([p.x, p.y, p.z]) for p in obstacle.points[:3])
    x = p1 - p0
    x /= max(float(np.linalg.norm(x)), 1e-12)
    z = np.cross(p1 - p0, p2 - p0)
    z /= max(float(np.linalg.norm(z)), 1e-12)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T[:3, 3] = p0
    return T


def form_from_obstacle(obstacle: Obstacle) -> ObstacleForm:
    if isinstance(obstacle, BoxObstacle):
        position = obstacle.centerPosition
        r = position.rotation
        return ObstacleForm(
            kind="BOX",
            name=obstacle.name,
            at_mm=_mm(position.point),
            rpy_deg=(math.degrees(r.roll), math.degrees(r.pitch), math.degrees(r.yaw)),
            size_mm=_mm(obstacle.sides),
        )
    if isinstance(obstacle, CapsuleObstacle):
        return ObstacleForm(
            kind="CAPSULE",
            name=obstacle.name,
            at_mm=_mm(obstacle.begin),
            end_mm=_mm(obstacle.finish),
            radius_mm=obstacle.radius * 1000.0,
        )
    position = matrix_to_position(plane_frame(obstacle))
    r = position.rotation
    return ObstacleForm(
        kind="PLANE",
        name=obstacle.name,
        at_mm=_mm(position.point),
        rpy_deg=(math.degrees(r.roll), math.degrees(r.pitch), math.degrees(r.yaw)),
    )


def tool_shape_from_text(text: str) -> ToolShape:
    """The Robot tab's one-line tool shape: capsules separated by ';', each `radius: x y z -> x y z` in mm in
    the flange frame (`30: 0 0 0 -> 0 0 150`). Empty: no capsules. ValueError says what is wrong."""
    capsules: list[SimplifiedCapsuleObstacle] = []
    for i, part in enumerate(p.strip() for p in text.split(";")):
        if not part:
            continue
        try:
            radius_text, ends = part.split(":", 1)
            begin_text, finish_text = ends.split("->", 1)
            radius = float(radius_text)
            begin = [float(v) for v in begin_text.split()]
            finish = [float(v) for v in finish_text.split()]
        except ValueError:
            raise ValueError(f"capsule {i + 1}: write it as 'radius: x y z -> x y z' (mm)") from None
        if len(begin) != 3 or len(finish) != 3:
            raise ValueError(f"capsule {i + 1}: each end needs three coordinates (x y z, mm)")
        values = [radius, *begin, *finish]
        if not all(math.isfinite(v) for v in values) or max(abs(v) for v in values) > SIZE_MM_MAX:
            raise ValueError(f"capsule {i + 1}: numbers must be finite and within ±{SIZE_MM_MAX:.0f} mm")
        if radius <= 0.0:
            raise ValueError(f"capsule {i + 1}: the radius must be more than 0 mm")
        capsules.append(
            SimplifiedCapsuleObstacle(
                radius=radius / 1000.0,
                begin=_point(np.asarray(begin) / 1000.0),
                finish=_point(np.asarray(finish) / 1000.0),
            )
        )
    try:
        return ToolShape(shape=capsules)
    except ValidationError as error:
        raise ValueError(error.errors()[0]["msg"]) from None


def text_from_tool_shape(shape: ToolShape) -> str:
    def xyz(point: Point) -> str:
        return " ".join(f"{v:g}" for v in (round(c, 3) for c in _mm(point)))

    return "; ".join(f"{c.radius * 1000.0:g}: {xyz(c.begin)} -> {xyz(c.finish)}" for c in shape.shape)
