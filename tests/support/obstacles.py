"""Obstacles for the cell tests, built as a script would send them."""

from __future__ import annotations

from pendant.controller import Point, Position, Rotation
from pendant.controller.cell_types import BoxObstacle


def box(name: str, xyz: tuple[float, float, float], side: float = 0.1) -> BoxObstacle:
    """A cube of `side` metres centred at `xyz` (metres, base frame), not rotated."""
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=side, y=side, z=side),
        centerPosition=Position(
            point=Point(x=xyz[0], y=xyz[1], z=xyz[2]), rotation=Rotation(roll=0, pitch=0, yaw=0)
        ),
    )
