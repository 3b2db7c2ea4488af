"""What jogging needs of an arm: its kinematics and a collision check. The arm model has both; so does
pendant.cell.geometry.CellAwareArm, whose check includes the cell (a jog stops short of an obstacle)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol

import numpy as np


class JogArm(Protocol):
    def fk(self, q: np.ndarray) -> np.ndarray: ...

    def ik(self, T_base_tcp: np.ndarray, q_near: np.ndarray) -> np.ndarray | None: ...

    def within_limits(self, q: np.ndarray) -> bool: ...

    def in_collision(self, q: np.ndarray) -> bool: ...

    def blocked_from(self, q_start: np.ndarray) -> Callable[[np.ndarray], bool]: ...

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]: ...
