"""Targets computed from taught waypoints: relative moves (offset in the base or tool frame), pallet cells."""

from __future__ import annotations

import math

import numpy as np

from pendant.controller.types import Point, Position, Rotation
from pendant.kinematics.transforms import matrix_to_position, position_to_matrix, rpy_to_matrix
from pendant.program.models import Frame, Offset

MM = 1e-3
ROUND_DECIMALS = 9  # nanometres / nano-radians: no float noise (-9.5e-15) in targets or exported files


def _r(value: float) -> float:
    return round(value, ROUND_DECIMALS) + 0.0  # + 0.0: no -0.0 either


def at(x: float, y: float, z: float, rotation: Rotation) -> Position:
    """A position from finite computed numbers, rounded so that computed zeros are 0.0, not -9.5e-15."""
    turn = Rotation(roll=_r(rotation.roll), pitch=_r(rotation.pitch), yaw=_r(rotation.yaw))
    return Position(point=Point(x=_r(x), y=_r(y), z=_r(z)), rotation=turn)


def clean(position: Position) -> Position:
    p = position.point
    return at(p.x, p.y, p.z, position.rotation)


def offset_position(position: Position, offset: Offset) -> Position:
    """`position` moved by `offset`: along the base axes (BASE) or the position's own axes (TOOL)."""
    T = position_to_matrix(position)
    delta = np.eye(4)
    delta[:3, :3] = rpy_to_matrix(*(math.radians(a) for a in (offset.rx, offset.ry, offset.rz)))
    delta[:3, 3] = np.array([offset.x, offset.y, offset.z]) * MM
    if offset.frame is Frame.TOOL:
        moved = T @ delta
    else:  # translate along base axes, turn about the TCP (not about the base origin)
        moved = np.eye(4)
        moved[:3, :3] = delta[:3, :3] @ T[:3, :3]
        moved[:3, 3] = T[:3, 3] + delta[:3, 3]
    return clean(matrix_to_position(moved))


def lifted(position: Position, height_m: float) -> Position:
    """`position` raised by `height_m` along the base z axis (a pallet's approach point)."""
    p = position.point
    return at(p.x, p.y, p.z + height_m, position.rotation)


def pallet_cells(
    corners: tuple[Position, Position, Position], rows: int, columns: int, layers: int, layer_height_m: float
) -> list[Position]:
    """Cells row by row, layer by layer (bottom first), all turned like the first corner.

    corners: the first cell, the last cell of the first row, the last cell of the first column."""
    origin, row_end, column_end = (np.array([c.point.x, c.point.y, c.point.z]) for c in corners)
    along_row = (row_end - origin) / max(columns - 1, 1)
    along_column = (column_end - origin) / max(rows - 1, 1)
    cells: list[Position] = []
    for layer in range(layers):
        for row in range(rows):
            for column in range(columns):
                x, y, z = (origin + row * along_column + column * along_row).tolist()
                cells.append(at(x, y, z + layer * layer_height_m, corners[0].rotation))
    return cells
