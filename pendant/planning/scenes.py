"""Cells to plan in, shipped for the benchmark (benchmarks/planning.py) and the tests: obstacles as the
controller holds them, a tool shape, a start and targets whose straight joint path is blocked.

Each scene has its named target (the move it is about) and, for a success rate over more than one move,
targets drawn at random from a fixed seed among configurations clear of the padded cell whose straight path
from the start is blocked.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pendant.controller.cell_types import (
    BoxObstacle,
    CapsuleObstacle,
    Obstacle,
    PlaneObstacle,
    SimplifiedCapsuleObstacle,
    ToolShape,
)
from pendant.controller.types import Point, Position, Rotation, Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.cell_shapes import cell_check

HOME_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)
LEVEL = Rotation(roll=0.0, pitch=0.0, yaw=0.0)
FLANGE = Tool(name="flange", point=Point(x=0.0, y=0.0, z=0.0), rotation=LEVEL, radius=0.0)
NO_SHAPE = ToolShape(shape=[])
# Random targets: within these of the start, per joint (a third of a turn; the shoulder and elbow less).
_RANDOM_SPAN_DEG = np.array([120.0, 60.0, 90.0, 120.0, 120.0, 120.0])
_STRAIGHT_STEP_RAD = np.radians(1.0)


def _box(name: str, centre: tuple[float, float, float], sides: tuple[float, float, float]) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=sides[0], y=sides[1], z=sides[2]),
        centerPosition=Position(point=Point(x=centre[0], y=centre[1], z=centre[2]), rotation=LEVEL),
    )


def _post(name: str, x: float, y: float, radius: float, height: float) -> CapsuleObstacle:
    return CapsuleObstacle(
        obstacleType="CAPSULE",
        name=name,
        radius=radius,
        begin=Point(x=x, y=y, z=0.0),
        finish=Point(x=x, y=y, z=height),
    )


@dataclass(frozen=True)
class Scene:
    """A cell, a start and its named target (degrees, as the PULSE API gives poses)."""

    name: str
    description: str
    obstacles: tuple[Obstacle, ...]
    start_deg: tuple[float, ...]
    target_deg: tuple[float, ...]
    tool_shape: ToolShape = field(default=NO_SHAPE)

    def check(self, arm: ArmModel) -> CellCheck:
        return cell_check(arm, self.obstacles, self.tool_shape, FLANGE)

    def targets(self, arm: ArmModel, count: int, margin_m: float, seed: int = 0) -> list[np.ndarray]:
        """The named target and `count - 1` random ones (radians), each clear of the cell padded by
        `margin_m`, each with its straight joint path from the start blocked."""
        padded = self.check(arm).with_margin(margin_m)
        start = np.radians(self.start_deg)
        rng = np.random.default_rng(seed)
        targets = [np.radians(self.target_deg)]
        while len(targets) < count:
            q = start + np.radians(rng.uniform(-_RANDOM_SPAN_DEG, _RANDOM_SPAN_DEG))
            q = np.clip(q, arm.lower, arm.upper)
            if not padded.collides(q) and padded.path_collides(start, q, _STRAIGHT_STEP_RAD):
                targets.append(q)
        return targets


def _with_j1(degrees: float) -> tuple[float, ...]:
    return (degrees, *HOME_DEG[1:])


BOX = Scene(
    "box",
    "a 0.12 m box where the straight path from J1 -60 to +60 degrees passes",
    (_box("box", (-0.466, -0.121, 0.485), (0.12, 0.12, 0.12)),),
    _with_j1(-60.0),
    _with_j1(60.0),
)

SHELF = Scene(
    "shelf",
    "a shelf with three boards; the tool goes from above it to between the lower two",
    (
        _box("bottom board", (-0.78, -0.12, 0.02), (0.3, 0.7, 0.02)),
        _box("middle board", (-0.78, -0.12, 0.42), (0.3, 0.7, 0.02)),
        _box("top board", (-0.78, -0.12, 0.80), (0.3, 0.7, 0.02)),
    ),
    _with_j1(90.0),
    (0.0, -40.0, 80.0, -130.0, -90.0, 0.0),
)

POSTS = Scene(
    "posts",
    "two posts with a 0.24 m gap; the tool reaches through it",
    (
        _post("left post", -0.55, -0.06 + 0.15, 0.03, 0.6),
        _post("right post", -0.55, -0.06 - 0.15, 0.03, 0.6),
    ),
    _with_j1(90.0),
    (0.0, -40.0, 80.0, -130.0, -90.0, 0.0),
)

README_CELL = Scene(
    "readme cell",
    "the README's cell file: a table, a post, a wall and a 0.15 m tool",
    (
        _box("table", (0.5, 0.0, -0.03), (0.8, 1.2, 0.05)),
        _post("post", 0.4, 0.3, 0.04, 0.6),
        PlaneObstacle(
            obstacleType="PLANE",
            name="wall",
            points=[Point(x=0.0, y=-0.5, z=0.0), Point(x=1.0, y=-0.5, z=0.0), Point(x=0.0, y=-0.5, z=1.0)],
        ),
    ),
    HOME_DEG,
    (150.0, -60.0, 100.0, -130.0, -90.0, 0.0),
    ToolShape(
        shape=[
            SimplifiedCapsuleObstacle(radius=0.03, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.15))
        ]
    ),
)

SCENES = (BOX, SHELF, POSTS, README_CELL)
