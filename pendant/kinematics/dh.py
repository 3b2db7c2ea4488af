"""The published DH tables of the PULSE arms (manual Rev. 6, Annex I, Table I-1; standard DH, metres)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DHTable:
    """Standard DH: T_{i-1,i} = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i); the TCP is frame 6 turned +90 deg
    about its z axis."""

    name: str
    d: tuple[float, ...]
    a: tuple[float, ...]
    alpha: tuple[float, ...]
    tcp_yaw: float = math.pi / 2

    def as_arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.array(self.d), np.array(self.a), np.array(self.alpha)


_D = (0.2325, 0.0, 0.0, 0.1205, 0.1711, 0.1226)
_ALPHA = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)

DH_TABLES: dict[str, DHTable] = {
    "pulse75": DHTable("pulse75", _D, (0.0, -0.375, -0.295, 0.0, 0.0, 0.0), _ALPHA),
    "pulse90": DHTable("pulse90", _D, (0.0, -0.450, -0.370, 0.0, 0.0, 0.0), _ALPHA),
}
