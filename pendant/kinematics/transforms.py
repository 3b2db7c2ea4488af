"""Rigid transforms: Position <-> 4x4, roll/pitch/yaw, rotation vectors.

Rotations follow the project convention R = Rz(yaw) Ry(pitch) Rx(roll); transforms are named T_a_b.
"""

from __future__ import annotations

import math

import numpy as np

from pendant.controller.types import Point, Position, Rotation


def rpy_to_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_to_rpy(R: np.ndarray) -> tuple[float, float, float]:
    """(roll, pitch, yaw) of R; at pitch = +-90 degrees roll is set to 0 and yaw takes the whole turn."""
    sp = -float(R[2, 0])
    if abs(sp) < 1.0 - 1e-12:
        pitch = math.asin(sp)
        roll = math.atan2(float(R[2, 1]), float(R[2, 2]))
        yaw = math.atan2(float(R[1, 0]), float(R[0, 0]))
    else:  # gimbal lock: only roll - yaw (or roll + yaw) is defined
        pitch = math.copysign(math.pi / 2, sp)
        roll = 0.0
        yaw = math.atan2(-float(R[0, 1]), float(R[1, 1]))
    return roll, pitch, yaw


def position_to_matrix(position: Position) -> np.ndarray:
    T = np.eye(4)
    r = position.rotation
    T[:3, :3] = rpy_to_matrix(r.roll, r.pitch, r.yaw)
    p = position.point
    T[:3, 3] = (p.x, p.y, p.z)
    return T


def matrix_to_position(T: np.ndarray) -> Position:
    roll, pitch, yaw = matrix_to_rpy(T[:3, :3])
    x, y, z = (float(v) for v in T[:3, 3])
    return Position(point=Point(x=x, y=y, z=z), rotation=Rotation(roll=roll, pitch=pitch, yaw=yaw))


def inverse(T: np.ndarray) -> np.ndarray:
    """Inverse of a rigid transform."""
    R = T[:3, :3]
    out = np.eye(4)
    out[:3, :3] = R.T
    out[:3, 3] = -R.T @ T[:3, 3]
    return out


def rotvec_to_matrix(w: np.ndarray) -> np.ndarray:
    """Rodrigues: the rotation by |w| radians about w."""
    angle = float(np.linalg.norm(w))
    if angle < 1e-12:
        return np.eye(3)
    k = w / angle
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1.0 - math.cos(angle)) * (K @ K)


def matrix_to_rotvec(R: np.ndarray) -> np.ndarray:
    """The rotation vector (axis * angle, angle in [0, pi]) of R."""
    cos_angle = max(-1.0, min(1.0, (float(np.trace(R)) - 1.0) / 2.0))
    angle = math.acos(cos_angle)
    if angle < 1e-9:
        return np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2.0
    if angle > math.pi - 1e-6:
        # Near a half turn the antisymmetric part vanishes: take the axis from the symmetric part.
        B = (R + np.eye(3)) / 2.0
        axis = np.sqrt(np.clip(np.diag(B), 0.0, None))
        i = int(np.argmax(axis))
        axis = B[i] / axis[i]
        return axis / np.linalg.norm(axis) * angle
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return w * (angle / (2.0 * math.sin(angle)))


def rotation_angle(R_a: np.ndarray, R_b: np.ndarray) -> float:
    """The angle in radians of the rotation taking R_a to R_b."""
    cos_angle = (float(np.trace(R_a.T @ R_b)) - 1.0) / 2.0
    return math.acos(max(-1.0, min(1.0, cos_angle)))
