"""Targets computed from taught waypoints: relative moves (offset in the base or tool frame), pallet cells."""

from __future__ import annotations

import math

import numpy as np

from pendant.controller.types import Position
from pendant.kinematics.transforms import matrix_to_position, position_to_matrix, rpy_to_matrix
from pendant.program.models import Frame, Offset

MM = 1e-3
ROUND_DECIMALS = 9  # nanometres / nano-radians: no float noise (-9.5e-15) in targets or exported files


def clean(position: Position) -> Position:
    """`position` rounded so that computed zeros are 0.0, not -9.5e-15."""
    data = position.model_dump()
    for group in ("point", "rotation"):
        data[group] = {k: round(v, ROUND_DECIMALS) + 0.0 for k, v in data[group].items()}
    return Position.model_validate(data)


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
    data = position.model_dump()
    data["point"]["z"] += height_m
    return clean(Position.model_validate(data))


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
                point = origin + row * along_column + column * along_row
                data = corners[0].model_dump()
                data["point"] = {"x": point[0], "y": point[1], "z": point[2] + layer * layer_height_m}
                cells.append(clean(Position.model_validate(data)))
    return cells
