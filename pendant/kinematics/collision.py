"""Self-collision and floor checks on the URDF's collision shapes (pinocchio + coal).

Checked pairs: every two shapes on links that are neither the same rigid body nor parent and child (after the
gripper fingers are locked, the gripper is part of link6's body), plus every shape except the base's against
the floor, a coal half-space z <= 0.
"""

from __future__ import annotations

from collections.abc import Callable

import coal
import numpy as np
import pinocchio as pin

FLOOR_NAME = "floor"
UNIVERSE_JOINT = 0


def link_name(shape_name: str) -> str:
    """The link a collision shape of the URDF belongs to ("link5" of "link5_0"), for contact messages."""
    return shape_name.rsplit("_", 1)[0] if shape_name[-1:].isdigit() else shape_name


class ArmCollision:
    """Collision model and scratch data of one reduced (6-joint) pinocchio model; not thread-safe."""

    def __init__(
        self,
        model: pin.Model,
        geometry_model: pin.GeometryModel,
        to_pin: Callable[[np.ndarray], np.ndarray] = lambda q: q,
    ) -> None:
        self.model = model
        self.data = model.createData()
        self.geometry_model = geometry_model
        self._to_pin = to_pin
        arm_shapes = list(range(geometry_model.ngeoms))
        floor = pin.GeometryObject(
            FLOOR_NAME,
            UNIVERSE_JOINT,
            pin.SE3.Identity(),
            # coal's half-space {x : n.x <= d}: everything at or below z = 0.
            coal.Halfspace(np.array([0.0, 0.0, 1.0]), 0.0),
        )
        floor_id = geometry_model.addGeometryObject(floor)
        objects = geometry_model.geometryObjects
        for i in arm_shapes:
            for j in arm_shapes[i + 1 :]:
                if not self._rigidly_or_directly_joined(objects[i].parentJoint, objects[j].parentJoint):
                    geometry_model.addCollisionPair(pin.CollisionPair(i, j))
            if objects[i].parentJoint != UNIVERSE_JOINT:
                geometry_model.addCollisionPair(pin.CollisionPair(i, floor_id))
        self.geometry_data = pin.GeometryData(geometry_model)

    def _rigidly_or_directly_joined(self, joint_a: int, joint_b: int) -> bool:
        parents = self.model.parents
        return joint_a == joint_b or parents[joint_a] == joint_b or parents[joint_b] == joint_a

    def in_collision(self, q: np.ndarray) -> bool:
        return bool(
            pin.computeCollisions(
                self.model, self.data, self.geometry_model, self.geometry_data, self._to_pin(q), True
            )
        )

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]:
        pin.computeCollisions(
            self.model, self.data, self.geometry_model, self.geometry_data, self._to_pin(q), False
        )
        objects = self.geometry_model.geometryObjects
        pairs = []
        for index, pair in enumerate(self.geometry_model.collisionPairs):
            if self.geometry_data.collisionResults[index].isCollision():
                pairs.append((objects[pair.first].name, objects[pair.second].name))
        return pairs

    def moving_shapes(self, q: np.ndarray) -> list[tuple[coal.CollisionGeometry, np.ndarray]]:
        """Every shape on a moving link (not the base, not the floor) with its pose T_base_shape at q."""
        pin.updateGeometryPlacements(
            self.model, self.data, self.geometry_model, self.geometry_data, self._to_pin(q)
        )
        objects = self.geometry_model.geometryObjects
        return [
            (objects[i].geometry, self.geometry_data.oMg[i].homogeneous.copy())
            for i in range(len(objects))
            if objects[i].parentJoint != UNIVERSE_JOINT
        ]

    def moving_shape_names(self) -> list[str]:
        """The names of `moving_shapes`' shapes, in the same order ("link3_1": link3's second shape)."""
        objects = self.geometry_model.geometryObjects
        return [objects[i].name for i in range(len(objects)) if objects[i].parentJoint != UNIVERSE_JOINT]

    @property
    def pair_count(self) -> int:
        return len(self.geometry_model.collisionPairs)
