"""The cell drawn in 3D: the controller's obstacles, translucent orange (red where the arm or the ghost
touches them), and the tool's capsules on the flange."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import viser
import viser.transforms as vtf

from pendant.cell.forms import plane_frame
from pendant.controller.cell_types import BoxObstacle, CapsuleObstacle, Obstacle, ToolShape
from pendant.controller.types import Point
from pendant.kinematics.obstacles import Capsule, capsule_shape
from pendant.kinematics.transforms import position_to_matrix

OBSTACLE_RGB = (255, 146, 43)
TOUCHING_RGB = (230, 30, 30)
TOOL_RGB = (120, 120, 130)
OBSTACLE_OPACITY = 0.5
TOUCHING_OPACITY = 0.75
PLANE_SIZE_M = 2.0  # a plane is infinite; this much of it is drawn around its first point
PLANE_THICKNESS_M = 0.002


def _vector(point: Point) -> np.ndarray:
    return np.array([point.x, point.y, point.z])


def _pose(T: np.ndarray) -> dict[str, np.ndarray]:
    return {"wxyz": vtf.SO3.from_matrix(T[:3, :3]).wxyz, "position": T[:3, 3]}


def add_capsule(
    scene: viser.SceneApi, name: str, capsule: Capsule, color: tuple[int, int, int], opacity: float
) -> list[viser.SceneNodeHandle]:
    """A capsule as a cylinder between two spheres (viser has no capsule primitive)."""
    _, T = capsule_shape(capsule)
    length = float(np.linalg.norm(capsule.b - capsule.a))
    radius = max(capsule.radius, 1e-4)
    nodes: list[viser.SceneNodeHandle] = []
    if length > 1e-9:
        nodes.append(
            scene.add_cylinder(
                f"{name}/body", radius=radius, height=length, color=color, opacity=opacity, **_pose(T)
            )
        )
    for end, point in (("a", capsule.a), ("b", capsule.b)):
        nodes.append(
            scene.add_icosphere(
                f"{name}/{end}",
                radius=radius,
                color=color,
                opacity=opacity,
                position=point,
                cast_shadow=False,
            )
        )
    return nodes


def add_obstacle(
    scene: viser.SceneApi, name: str, obstacle: Obstacle, color: tuple[int, int, int], opacity: float
) -> list[viser.SceneNodeHandle]:
    if isinstance(obstacle, BoxObstacle):
        T = position_to_matrix(obstacle.centerPosition)
        sides = tuple(float(v) for v in _vector(obstacle.sides))
        return [scene.add_box(name, color=color, dimensions=sides, opacity=opacity, **_pose(T))]
    if isinstance(obstacle, CapsuleObstacle):
        capsule = Capsule(obstacle.radius, _vector(obstacle.begin), _vector(obstacle.finish))
        return add_capsule(scene, name, capsule, color, opacity)
    T = plane_frame(obstacle)
    T[:3, 3] -= T[:3, 2] * (PLANE_THICKNESS_M / 2.0)
    dimensions = (PLANE_SIZE_M, PLANE_SIZE_M, PLANE_THICKNESS_M)
    return [
        scene.add_box(name, color=color, dimensions=dimensions, opacity=opacity, side="double", **_pose(T))
    ]


class ObstacleDrawing:
    """Obstacles under `root` in `scene`; redraws only what changed (each node is a message per browser)."""

    def __init__(self, scene: viser.SceneApi, root: str, *, only_touching: bool = False) -> None:
        self._scene = scene
        self._root = root
        self._only_touching = only_touching  # an overlay: draw just the touched ones, in red
        self._drawn: dict[str, tuple[Obstacle, bool, list[viser.SceneNodeHandle]]] = {}

    @property
    def shown(self) -> dict[str, bool]:
        """Each drawn obstacle's name and whether it is drawn red (touching)."""
        return {name: touching for name, (_, touching, _) in self._drawn.items()}

    def show(self, obstacles: Sequence[Obstacle], touching: Sequence[str] = ()) -> None:
        wanted = {
            o.name: (o, o.name in touching)
            for o in obstacles
            if not self._only_touching or o.name in touching
        }
        for name in [n for n in self._drawn if n not in wanted or self._drawn[n][:2] != wanted[n]]:
            for node in self._drawn.pop(name)[2]:
                node.remove()
        for index, (name, (obstacle, red)) in enumerate(wanted.items()):
            if name in self._drawn:
                continue
            color = TOUCHING_RGB if red else OBSTACLE_RGB
            opacity = TOUCHING_OPACITY if red else OBSTACLE_OPACITY
            node_name = f"{self._root}/o{index}_{abs(hash(name)) % 10**8}"
            self._drawn[name] = (
                obstacle,
                red,
                add_obstacle(self._scene, node_name, obstacle, color, opacity),
            )


class ToolShapeDrawing:
    """The tool's capsules on the flange: a frame that follows the flange, the capsules inside it."""

    def __init__(self, scene: viser.SceneApi, root: str = "/tool_shape") -> None:
        self._scene = scene
        self._frame = scene.add_frame(root, show_axes=False)
        self._root = root
        self._shape: ToolShape | None = None
        self._nodes: list[viser.SceneNodeHandle] = []

    @property
    def frame(self) -> viser.FrameHandle:
        """The frame on the flange that the capsules are drawn in."""
        return self._frame

    @property
    def capsules_shown(self) -> int:
        return len(self._shape.shape) if self._shape is not None else 0

    def show(self, shape: ToolShape, T_base_flange: np.ndarray | None) -> None:
        if shape != self._shape:
            for node in self._nodes:
                node.remove()
            self._nodes = []
            for i, c in enumerate(shape.shape):
                capsule = Capsule(c.radius, _vector(c.begin), _vector(c.finish))
                self._nodes += add_capsule(self._scene, f"{self._root}/c{i}", capsule, TOOL_RGB, 0.8)
            self._shape = shape
        if T_base_flange is not None and self._nodes:
            pose = _pose(T_base_flange)
            if not np.allclose(self._frame.position, pose["position"]) or not np.allclose(
                self._frame.wxyz, pose["wxyz"]
            ):
                self._frame.position = pose["position"]
                self._frame.wxyz = pose["wxyz"]
