"""Closed-form inverse kinematics of UR-type arms (numpy only), after Hawkins' UR-5/UR-10 derivation.

Eight branches: shoulder (two q1), wrist (sign of sin q5), elbow (sign of sin q3). The derivation used here:

- The wrist centre p05 = p - d6 z_tcp lies at height d4 along z1, which gives q1 = phi + asin(d4 / r) or
  phi + pi - asin(d4 / r).
- In frame 1 the orientation is R_1_tcp = Rz(q234) Ry(-q5) Rz(q6 + tcp_yaw), a ZYZ Euler form. Its last row
  (s5 cos g, -s5 sin g, c5) gives g = q6 + tcp_yaw for each sign of s5; then M = R_1_tcp Rz(-g) = Rz(q234)
  Ry(-q5) yields q234 and q5 by atan2 of entries that stay well-conditioned even when s5 -> 0. In the
  wrist singularity (s5 = 0) only q234 +- q6 is fixed and q2, q3, q4, q6 turn about parallel axes (a
  self-motion): q6 is taken from the caller's `q6_free` unless that leaves joint 4 out of the 2R arm's reach,
  in which case the nearest reachable point of the self-motion is used. Nothing is divided by s5, so no NaN.
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
    # Squared distances from J2 to joint 4's origin that the 2R arm spans (folded .. stretched).
    e_min_sq = a_sq - abs(two_a2a3)
    e_max_sq = a_sq + abs(two_a2a3)
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
        singular = math.hypot(m20, m21) < WRIST_SINGULAR_TOL
        g_base = q6_free + yaw if singular else math.atan2(-m21, m20)
        for g in (g_base, g_base + math.pi):
            q234, q5 = _q234_q5(m00, m01, m10, m11, m20, m21, m22, g)
            if singular:
                # q2, q3, q4 and q6 then turn about parallel axes: a self-motion that moves joint 4's
                # origin on a circle of radius d5 about the wrist centre. Keep q6 unless that puts joint 4
                # out of the 2R arm's reach; then move along the self-motion to the nearest reachable point.
                reachable = _nearest_reachable_q234(q234, px1, py1, d5, e_min_sq, e_max_sq)
                if reachable is None:
                    continue
                if reachable != q234:
                    # c5 = +1: q234 + g is fixed; c5 = -1: q234 - g is fixed.
                    g += (q234 - reachable) if m22 > 0.0 else (reachable - q234)
                    q234, q5 = _q234_q5(m00, m01, m10, m11, m20, m21, m22, g)
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


def _q234_q5(
    m00: float, m01: float, m10: float, m11: float, m20: float, m21: float, m22: float, g: float
) -> tuple[float, float]:
    """q234 and q5 from R_1_tcp (entries m..) once g = q6 + tcp_yaw is chosen: M = R_1_tcp Rz(-g) =
    Rz(q234) Ry(-q5), read off by atan2 of entries that stay well-conditioned for every q5."""
    cg = math.cos(g)
    sg = math.sin(g)
    n01 = m00 * sg + m01 * cg
    n11 = m10 * sg + m11 * cg
    n20 = m20 * cg - m21 * sg
    return math.atan2(-n01, n11), math.atan2(n20, m22)


def _nearest_reachable_q234(
    q234: float, wx: float, wy: float, d5: float, e_min_sq: float, e_max_sq: float
) -> float | None:
    """q234 itself if joint 4's origin w - d5 (s234, -c234) is within the 2R arm's reach, else the nearest
    q234 (by angle) for which it is, or None when no q234 works."""
    w_sq = wx * wx + wy * wy
    w = math.sqrt(w_sq)
    # |e|^2 = |w|^2 + d5^2 - 2 d5 |w| sin(q234 - psi), psi = atan2(wy, wx).
    if w < 1e-12:
        return q234 if e_min_sq <= d5 * d5 <= e_max_sq else None
    psi = math.atan2(wy, wx)
    lo = (w_sq + d5 * d5 - e_max_sq) / (2.0 * d5 * w)
    hi = (w_sq + d5 * d5 - e_min_sq) / (2.0 * d5 * w)
    if lo > 1.0 or hi < -1.0:
        return None
    theta = q234 - psi
    if lo <= math.sin(theta) <= hi:
        return q234
    # The reachable set is one or two arcs of theta; the nearest point is one of their ends.
    ends = []
    for bound in (max(lo, -1.0), min(hi, 1.0)):
        edge = math.asin(bound)
        ends += [edge, math.pi - edge]
    nearest = min(ends, key=lambda end: abs(math.remainder(end - theta, 2.0 * math.pi)))
    return psi + nearest


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
