"""ArmModel: one PULSE arm's kinematics, collision and dynamics behind a numpy-in, numpy-out API.

Forward and inverse kinematics are closed-form from the DH table (fast, no URDF needed); the Jacobian,
dynamics and collision checks use pinocchio on the URDF, loaded on first use.
"""

from __future__ import annotations

import functools
import math
import threading
from collections.abc import Callable
from pathlib import Path

import numpy as np

from pendant.kinematics import analytic_ik, dh_fk
from pendant.kinematics.dh import DH_TABLES, DHTable
from pendant.kinematics.limits import JOINT_LOWER_RAD, JOINT_UPPER_RAD, N_JOINTS
from pendant.kinematics.pin_model import PinArm
from pendant.paths import urdf_path as resolve_urdf_path

# An IK answer must reproduce the target this closely through FK, or it is dropped.
IK_POS_TOL_M = 1e-6
IK_ROT_TOL_RAD = 1e-6
# Two IK branches closer than this (per joint, radians) are the same solution.
_DUPLICATE_TOL_RAD = 1e-7


class ArmModel:
    """A PULSE arm: `ArmModel.load("pulse75")`, then fk / ik / ik_all / jacobian / collision / dynamics.

    Radians and metres throughout; joint vectors are (6,), poses are T_base_tcp (4, 4).
    """

    def __init__(
        self,
        table: DHTable,
        urdf_path: Path | None = None,
        lower: np.ndarray = JOINT_LOWER_RAD,
        upper: np.ndarray = JOINT_UPPER_RAD,
    ) -> None:
        dh_fk.check_ur_geometry(table)
        self.table = table
        self.name = table.name
        self.urdf_path = urdf_path
        self.lower = np.array(lower, dtype=float)
        self.upper = np.array(upper, dtype=float)
        self.lower.flags.writeable = False
        self.upper.flags.writeable = False
        self._midpoint = 0.5 * (self.lower + self.upper)
        # pinocchio's Data is scratch space: one caller at a time (viser and FastAPI run in threads).
        self._pin_lock = threading.Lock()

    @classmethod
    def load(cls, model: str | Path) -> ArmModel:
        """A named model ("pulse75", "pulse90"), or a URDF path whose file stem or robot name is one."""
        path = resolve_urdf_path(str(model))
        key = str(model) if str(model) in DH_TABLES else _model_key_of_urdf(path)
        return cls(DH_TABLES[key], path)

    def __repr__(self) -> str:
        return f"ArmModel({self.name!r}, urdf_path={str(self.urdf_path)!r})"

    # --- kinematics (closed form) -------------------------------------------------------------------

    def fk(self, q: np.ndarray) -> np.ndarray:
        """T_base_tcp (4, 4) for joint angles q (6,)."""
        return dh_fk.fk(self.table, joint_vector(q))

    def dh_frames(self, q: np.ndarray) -> np.ndarray:
        """T_base_i of the DH frames 0..6 and the TCP, shape (8, 4, 4)."""
        return dh_fk.dh_link_frames(self.table, joint_vector(q))

    def ik_all(self, T_base_tcp: np.ndarray, q_near: np.ndarray | None = None) -> np.ndarray:
        """Every IK branch within the joint limits, shape (k, 6), k <= 8 (k = 0 when unreachable).

        Each joint is given as its 2*pi-equivalent nearest the middle of its limits. `q_near` only picks q6
        in a wrist singularity (default: the middle of the limits).
        """
        T = _transform(T_base_tcp)
        q6_free = float(self._midpoint[5] if q_near is None else joint_vector(q_near)[5])
        raw = analytic_ik.ik_branches(self.table, T, q6_free)
        if not raw:
            return np.empty((0, N_JOINTS))
        wrapped, in_limits = analytic_ik.nearest_equivalents(
            np.array(raw), self._midpoint, self.lower, self.upper
        )
        kept: list[np.ndarray] = []
        for q in wrapped[in_limits]:
            if any(np.max(np.abs(q - other)) < _DUPLICATE_TOL_RAD for other in kept):
                continue
            if self._reaches(T, q):
                kept.append(q)
        return np.array(kept) if kept else np.empty((0, N_JOINTS))

    def ik(self, T_base_tcp: np.ndarray, q_near: np.ndarray) -> np.ndarray | None:
        """The IK solution nearest q_near (6,) within the limits, or None when the target is unreachable."""
        T = _transform(T_base_tcp)
        near = joint_vector(q_near)
        raw = analytic_ik.ik_branches(self.table, T, float(near[5]))
        if not raw:
            return None
        candidates, in_limits = analytic_ik.nearest_equivalents(np.array(raw), near, self.lower, self.upper)
        distances = np.where(in_limits, np.sum((candidates - near) ** 2, axis=1), np.inf)
        for index in np.argsort(distances):
            if not math.isfinite(distances[index]):
                break
            if self._reaches(T, candidates[index]):
                return candidates[index]
        return None

    def _reaches(self, T: np.ndarray, q: np.ndarray) -> bool:
        pos_err, rot_err = analytic_ik.pose_error(T, dh_fk.fk_flat(self.table, q.tolist()))
        return pos_err < IK_POS_TOL_M and rot_err < IK_ROT_TOL_RAD

    def within_limits(self, q: np.ndarray) -> bool:
        q = joint_vector(q)
        return bool(np.all(q >= self.lower) and np.all(q <= self.upper))

    # --- pinocchio: Jacobian, dynamics, collision -------------------------------------------------------

    @functools.cached_property
    def _pin(self) -> PinArm:
        if self.urdf_path is None:
            raise RuntimeError(
                f"arm model {self.name!r} has no URDF: Jacobian, dynamics and collision need one"
            )
        return PinArm(self.urdf_path)

    @property
    def pin_arm(self) -> PinArm:
        """The pinocchio model and collision geometry (loaded on first use; its data is not thread-safe)."""
        return self._pin

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """Geometric Jacobian of the TCP in base axes, (6, 6): rows vx vy vz wx wy wz, columns joints."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.tcp_jacobian(q)

    def fk_all_links(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """T_base_link (4, 4) of every URDF link (base_link, link1..link6, tcp, gripper parts)."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.link_poses(q)

    def gravity_torques(self, q: np.ndarray) -> np.ndarray:
        """Joint torques (6,) in N m that hold the arm still against gravity at q."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.gravity(q)

    def inverse_dynamics(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
        """Joint torques (6,) in N m for joint positions, velocities and accelerations (RNEA)."""
        q, dq, ddq = joint_vector(q), joint_vector(dq, "dq"), joint_vector(ddq, "ddq")
        with self._pin_lock:
            return self._pin.rnea(q, dq, ddq)

    def in_collision(self, q: np.ndarray) -> bool:
        """True when two non-adjacent links touch or any link but the base dips below the floor (z = 0)."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.collision.in_collision(q)

    def moving_shapes(self, q: np.ndarray) -> list[tuple[object, np.ndarray]]:
        """(coal shape, T_base_shape) of every collision shape on a moving link at q (obstacle checks)."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.collision.moving_shapes(q)

    def blocked_from(self, q_start: np.ndarray) -> Callable[[np.ndarray], bool]:
        """The collision test for the samples of one motion from q_start (the arm alone: `in_collision`;
        an arm with a cell adds the contact rule, see pendant.cell.geometry.CellAwareArm)."""
        return self.in_collision

    def moving_shape_names(self) -> list[str]:
        """The URDF names of `moving_shapes`' shapes, in the same order (for messages)."""
        with self._pin_lock:
            return self._pin.collision.moving_shape_names()

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]:
        """The (geometry, geometry) name pairs in contact at q ("floor" for the floor), for messages."""
        q = joint_vector(q)
        with self._pin_lock:
            return self._pin.collision.colliding_pairs(q)


def joint_vector(q: object, what: str = "q") -> np.ndarray:
    array = np.asarray(q, dtype=float)
    if array.shape != (N_JOINTS,):
        raise ValueError(f"{what} must have shape ({N_JOINTS},), got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{what} must be finite, got {array.tolist()}")
    return array


def _transform(T: object) -> np.ndarray:
    array = np.asarray(T, dtype=float)
    if array.shape != (4, 4):
        raise ValueError(f"T_base_tcp must have shape (4, 4), got {array.shape}")
    if not np.all(np.isfinite(array)):
        raise ValueError("T_base_tcp must be finite")
    return array


def _model_key_of_urdf(path: Path) -> str:
    if path.stem in DH_TABLES:
        return path.stem
    import xml.etree.ElementTree as ElementTree

    robot_name = ElementTree.parse(path).getroot().get("name", "")
    for key in DH_TABLES:
        if robot_name.lower().replace("_", "").startswith(key):
            return key
    raise ValueError(f"{path}: no DH table for robot {robot_name!r}; expected one of {sorted(DH_TABLES)}")
