"""Forward kinematics from a DH table, in closed form (numpy only).

The PULSE arms have the UR geometry (alpha = [pi/2, 0, 0, pi/2, -pi/2, 0], a = [0, a2, a3, 0, 0, 0]), so
the chain collapses to a few products: R_1_tcp = Rz(q2+q3+q4) Ry(-q5) Rz(q6 + tcp_yaw), and the TCP's
position in frame 1 is a planar 2R arm plus the wrist offsets. Writing it out in Python floats is several
times faster than six 4x4 matrix products in numpy, which matters because IK checks its answers with it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from pendant.kinematics.dh import DHTable

_ALPHA_UR = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)


def check_ur_geometry(table: DHTable) -> None:
    """Raise ValueError unless the table has the UR-type structure the closed forms assume."""
    if len(table.d) != 6 or len(table.a) != 6 or len(table.alpha) != 6:
        raise ValueError(f"DH table {table.name!r} must have 6 rows")
    alpha_ok = all(math.isclose(x, y, abs_tol=1e-12) for x, y in zip(table.alpha, _ALPHA_UR, strict=True))
    a_ok = table.a[0] == 0.0 and table.a[3] == 0.0 and table.a[4] == 0.0 and table.a[5] == 0.0
    d_ok = table.d[1] == 0.0 and table.d[2] == 0.0
    if not (alpha_ok and a_ok and d_ok) or abs(abs(table.a[1]) - abs(table.a[2])) < 1e-9:
        raise ValueError(f"DH table {table.name!r} is not of the UR type (three parallel middle axes)")


def fk_flat(table: DHTable, q: Sequence[float] | np.ndarray) -> tuple[float, ...]:
    """T_base_tcp as 12 floats, row-major rotation then position: (r00..r22, x, y, z). No checks."""
    d1, _, _, d4, d5, d6 = table.d
    a2 = table.a[1]
    a3 = table.a[2]
    q1, q2, q3, q4, q5, q6 = q
    c1 = math.cos(q1)
    s1 = math.sin(q1)
    q23 = q2 + q3
    q234 = q23 + q4
    ca = math.cos(q234)
    sa = math.sin(q234)
    c5 = math.cos(q5)
    s5 = math.sin(q5)
    g = q6 + table.tcp_yaw
    cg = math.cos(g)
    sg = math.sin(g)
    # R_1_tcp = Rz(q234) Ry(-q5) Rz(g), the ZYZ Euler form with beta = -q5.
    m00 = ca * c5 * cg - sa * sg
    m01 = -ca * c5 * sg - sa * cg
    m02 = -ca * s5
    m10 = sa * c5 * cg + ca * sg
    m11 = -sa * c5 * sg + ca * cg
    m12 = -sa * s5
    m20 = s5 * cg
    m21 = -s5 * sg
    # TCP origin in frame 1: planar 2R arm, wrist offsets d5 along z4 and d6 along z6, d4 out of the plane.
    px = a2 * math.cos(q2) + a3 * math.cos(q23) + d5 * sa + d6 * m02
    py = a2 * math.sin(q2) + a3 * math.sin(q23) - d5 * ca + d6 * m12
    pz = d4 + d6 * c5
    # R_0_1 has columns x1 = (c1, s1, 0), y1 = (0, 0, 1), z1 = (s1, -c1, 0), origin (0, 0, d1).
    return (
        c1 * m00 + s1 * m20,
        c1 * m01 + s1 * m21,
        c1 * m02 + s1 * c5,
        s1 * m00 - c1 * m20,
        s1 * m01 - c1 * m21,
        s1 * m02 - c1 * c5,
        m10,
        m11,
        m12,
        c1 * px + s1 * pz,
        s1 * px - c1 * pz,
        d1 + py,
    )


def fk(table: DHTable, q: Sequence[float] | np.ndarray) -> np.ndarray:
    """T_base_tcp (4, 4) for joint angles q (6,) in radians."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22, x, y, z = fk_flat(table, q)
    return np.array(
        [[r00, r01, r02, x], [r10, r11, r12, y], [r20, r21, r22, z], [0.0, 0.0, 0.0, 1.0]], dtype=float
    )


def dh_link_frames(table: DHTable, q: Sequence[float] | np.ndarray) -> np.ndarray:
    """T_base_i for the DH frames 0..6 and the TCP, shape (8, 4, 4), by the generic DH product.

    Slower than `fk` but independent of its algebra, so tests use it as a reference; the simulator can use
    it to place links.
    """
    frames = np.empty((8, 4, 4))
    frames[0] = np.eye(4)
    for i in range(6):
        ct, st = math.cos(q[i]), math.sin(q[i])
        ca, sa = math.cos(table.alpha[i]), math.sin(table.alpha[i])
        a, d = table.a[i], table.d[i]
        step = np.array(
            [
                [ct, -st * ca, st * sa, a * ct],
                [st, ct * ca, -ct * sa, a * st],
                [0.0, sa, ca, d],
                [0, 0, 0, 1.0],
            ]
        )
        frames[i + 1] = frames[i] @ step
    cy, sy = math.cos(table.tcp_yaw), math.sin(table.tcp_yaw)
    yaw = np.array([[cy, -sy, 0, 0], [sy, cy, 0, 0], [0, 0, 1.0, 0], [0, 0, 0, 1.0]])
    frames[7] = frames[6] @ yaw
    return frames
