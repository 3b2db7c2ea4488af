"""Closed-form inverse kinematics of UR-type arms (numpy only), after Hawkins' UR-5/UR-10 derivation.

Eight branches: shoulder (two q1), wrist (sign of sin q5), elbow (sign of sin q3). The derivation used here:

- The wrist centre p05 = p - d6 z_tcp lies at height d4 along z1, which gives q1 = phi + asin(d4 / r) or
  phi + pi - asin(d4 / r).
- In frame 1 the orientation is R_1_tcp = Rz(q234) Ry(-q5) Rz(q6 + tcp_yaw), a ZYZ Euler form. Its last row
  (s5 cos g, -s5 sin g, c5) gives g = q6 + tcp_yaw for each sign of s5; then M = R_1_tcp Rz(-g) = Rz(q234)
  Ry(-q5) yields q234 and q5 by atan2 of entries that stay well-conditioned even when s5 -> 0. In the
  wrist singularity (s5 = 0) only q234 +- q6 is fixed: q6 is taken from the caller's `q6_free` and q4
  absorbs the rest, so nothing is divided by s5 and no NaN appears.
- The joint-4 origin in frame 1 is the wrist centre minus d5 z4, and a planar 2R solve gives q2, q3.

Every branch that passes the reach tests is returned; the caller checks limits and verifies with FK.
"""

from __future__ import annotations

import math

import numpy as np

from pendant.kinematics.dh import DHTable

# Below this |sin q5| the wrist is treated as singular and q6 is chosen by the caller: the orientation
# error that choice can cause is at most |sin q5| * pi, far inside the FK check's tolerance.
WRIST_SINGULAR_TOL = 1e-8
# Reach tests are relaxed by this much (in the cosine / sine being clamped) so a target exactly at the
# boundary is not lost to rounding; FK verification then rejects anything really out of reach.
REACH_SLACK = 1e-7


def ik_branches(table: DHTable, T_base_tcp: np.ndarray, q6_free: float = 0.0) -> list[tuple[float, ...]]:
    """Up to eight joint solutions (radians, each in (-pi, pi] before tcp_yaw) for T_base_tcp (4, 4).

    No limit checks and no FK verification here. `q6_free` is used for q6 in a wrist singularity.
    """
    d1, _, _, d4, d5, d6 = table.d
    a2 = table.a[1]
    a3 = table.a[2]
    yaw = table.tcp_yaw
    (r00, r01, r02, x), (r10, r11, r12, y), (r20, r21, r22, z) = T_base_tcp[:3].tolist()

    # Wrist centre (origin of DH frame 5).
    wx = x - d6 * r02
    wy = y - d6 * r12
    wz = z - d1 - d6 * r22
    radius = math.hypot(wx, wy)
    if radius < d4 * (1.0 - REACH_SLACK) or radius == 0.0:
        return []
    phi = math.atan2(wy, wx)
    shoulder = math.asin(min(d4 / radius, 1.0))
    q1_options = (phi + shoulder, phi + math.pi - shoulder)

    a_sq = a2 * a2 + a3 * a3
    two_a2a3 = 2.0 * a2 * a3
    solutions: list[tuple[float, ...]] = []
    for q1 in q1_options:
        c1 = math.cos(q1)
        s1 = math.sin(q1)
        # R_1_tcp = R_0_1^T R: rows x1.R, y1.R, z1.R with x1 = (c1, s1, 0), y1 = (0, 0, 1), z1 = (s1, -c1, 0).
        m00 = c1 * r00 + s1 * r10
        m01 = c1 * r01 + s1 * r11
        m10 = r20
        m11 = r21
        m20 = s1 * r00 - c1 * r10
        m21 = s1 * r01 - c1 * r11
        m22 = s1 * r02 - c1 * r12
        # Wrist centre in frame 1 (its z1 component is d4 by construction of q1).
        px1 = c1 * wx + s1 * wy
        py1 = wz
        sin5_abs = math.hypot(m20, m21)
        if sin5_abs < WRIST_SINGULAR_TOL:
            g_base = q6_free + yaw
            g_options = (g_base, g_base + math.pi)
        else:
            g_base = math.atan2(-m21, m20)
            g_options = (g_base, g_base + math.pi)
        for g in g_options:
            cg = math.cos(g)
            sg = math.sin(g)
            # M = R_1_tcp Rz(-g) = Rz(q234) Ry(-q5).
            n01 = m00 * sg + m01 * cg
            n11 = m10 * sg + m11 * cg
            n20 = m20 * cg - m21 * sg
            q234 = math.atan2(-n01, n11)
            q5 = math.atan2(n20, m22)
            c234 = math.cos(q234)
            s234 = math.sin(q234)
            # Joint-4 origin in frame 1: the wrist centre minus d5 along z4 = (s234, -c234, 0).
            ex = px1 - d5 * s234
            ey = py1 + d5 * c234
            c3 = (ex * ex + ey * ey - a_sq) / two_a2a3
            if abs(c3) > 1.0 + REACH_SLACK:
                continue
            c3 = max(-1.0, min(1.0, c3))
            s3_abs = math.sqrt(1.0 - c3 * c3)
            base_angle = math.atan2(ey, ex)
            for s3 in (s3_abs, -s3_abs):
                q3 = math.atan2(s3, c3)
                q2 = base_angle - math.atan2(a3 * s3, a2 + a3 * c3)
                q4 = q234 - q2 - q3
                solutions.append((q1, q2, q3, q4, q5, g - yaw))
    return solutions


def pose_error(T_a: np.ndarray, flat_b: tuple[float, ...]) -> tuple[float, float]:
    """(position error m, rotation error rad) between T_a (4, 4) and a pose given as `fk_flat` output.

    The rotation error is ||R_a - R_b||_F / sqrt(2) = 2 sin(angle / 2), accurate for small angles where
    an arccos of the trace would lose half the digits.
    """
    (a00, a01, a02, ax), (a10, a11, a12, ay), (a20, a21, a22, az) = T_a[:3].tolist()
    b00, b01, b02, b10, b11, b12, b20, b21, b22, bx, by, bz = flat_b
    pos = math.sqrt((ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2)
    rot_sq = (
        (a00 - b00) ** 2
        + (a01 - b01) ** 2
        + (a02 - b02) ** 2
        + (a10 - b10) ** 2
        + (a11 - b11) ** 2
        + (a12 - b12) ** 2
        + (a20 - b20) ** 2
        + (a21 - b21) ** 2
        + (a22 - b22) ** 2
    )
    return pos, math.sqrt(rot_sq * 0.5)


def nearest_equivalents(
    solutions: np.ndarray, q_near: np.ndarray, lower: np.ndarray, upper: np.ndarray, slack: float = 1e-9
) -> tuple[np.ndarray, np.ndarray]:
    """Per joint, the 2*pi-equivalent of each solution (k, 6) nearest q_near that lies within the limits.

    Returns (angles (k, 6), in_limits (k,)). Distances separate per joint, so per-joint choice gives the
    nearest equivalent overall.
    """
    two_pi = 2.0 * math.pi
    shifted = solutions + two_pi * np.round((q_near - solutions) / two_pi)
    shifted = np.where(shifted > upper + slack, shifted - two_pi, shifted)
    shifted = np.where(shifted < lower - slack, shifted + two_pi, shifted)
    in_limits = np.all((shifted >= lower - slack) & (shifted <= upper + slack), axis=1)
    return np.clip(shifted, lower, upper), in_limits
