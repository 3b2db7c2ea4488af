"""The arm's URDF in pinocchio: a 6-joint model (gripper fingers locked) for Jacobian, dynamics, collision."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from pendant.kinematics.collision import ArmCollision

ARM_JOINTS = tuple(f"joint{i}" for i in range(1, 7))
TCP_FRAME = "tcp"


class PinArm:
    """pinocchio model, data and collision model of one URDF; not thread-safe (ArmModel holds a lock)."""

    def __init__(self, urdf_path: Path) -> None:
        urdf = str(urdf_path)
        package_dirs = [str(urdf_path.parent), str(urdf_path.parent.parent)]
        full_model = pin.buildModelFromUrdf(urdf)
        full_geometry = pin.buildGeomFromUrdf(
            full_model, urdf, pin.GeometryType.COLLISION, package_dirs=package_dirs
        )
        missing = [name for name in ARM_JOINTS if not full_model.existJointName(name)]
        if missing:
            raise ValueError(f"{urdf_path}: joints {missing} not found")
        # Everything that is not an arm joint (the gripper fingers) is locked at its neutral (closed) value.
        to_lock = [full_model.getJointId(name) for name in full_model.names[1:] if name not in ARM_JOINTS]
        model, geometry = pin.buildReducedModel(full_model, full_geometry, to_lock, pin.neutral(full_model))
        if model.nq != len(ARM_JOINTS) or model.nv != len(ARM_JOINTS):
            raise ValueError(f"{urdf_path}: expected 6 revolute arm joints, got nq={model.nq} nv={model.nv}")
        # Our joint order is joint1..joint6; pinocchio orders by the tree, which for a chain is the same,
        # but map explicitly so a reordered URDF cannot silently swap joints.
        self._q_index = np.array([model.joints[model.getJointId(name)].idx_q for name in ARM_JOINTS])
        self._identity_order = bool(np.array_equal(self._q_index, np.arange(len(ARM_JOINTS))))
        self.model = model
        self.data = model.createData()
        self.tcp_frame_id = model.getFrameId(TCP_FRAME)
        if self.tcp_frame_id >= model.nframes:
            raise ValueError(f"{urdf_path}: no frame named {TCP_FRAME!r}")
        self._link_frames = [
            (frame.name, index)
            for index, frame in enumerate(model.frames)
            if frame.type == pin.FrameType.BODY
        ]
        self.collision = ArmCollision(model, geometry, self.to_pin)

    def to_pin(self, q: np.ndarray) -> np.ndarray:
        if self._identity_order:
            return q
        q_pin = np.empty(self.model.nq)
        q_pin[self._q_index] = q
        return q_pin

    def _from_pin(self, v: np.ndarray) -> np.ndarray:
        return np.array(v if self._identity_order else v[self._q_index])

    def tcp_jacobian(self, q: np.ndarray) -> np.ndarray:
        J = pin.computeFrameJacobian(
            self.model, self.data, self.to_pin(q), self.tcp_frame_id, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )
        return np.array(J if self._identity_order else J[:, self._q_index])

    def tcp_pose(self, q: np.ndarray) -> np.ndarray:
        pin.framesForwardKinematics(self.model, self.data, self.to_pin(q))
        return self.data.oMf[self.tcp_frame_id].homogeneous.copy()

    def link_poses(self, q: np.ndarray) -> dict[str, np.ndarray]:
        pin.framesForwardKinematics(self.model, self.data, self.to_pin(q))
        return {name: self.data.oMf[index].homogeneous.copy() for name, index in self._link_frames}

    def gravity(self, q: np.ndarray) -> np.ndarray:
        return self._from_pin(pin.computeGeneralizedGravity(self.model, self.data, self.to_pin(q)))

    def rnea(self, q: np.ndarray, dq: np.ndarray, ddq: np.ndarray) -> np.ndarray:
        return self._from_pin(
            pin.rnea(self.model, self.data, self.to_pin(q), self.to_pin(dq), self.to_pin(ddq))
        )
