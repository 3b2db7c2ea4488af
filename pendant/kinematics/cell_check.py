"""The ONE collision checker: the arm's links (with each other and the floor), the tool's capsules and the
cell's obstacles in a single pinocchio GeometryModel, checked by pinocchio + coal in C++.

The simulator, the jog, the page's target check, the pre-flight and the planner all ask this class. A cell
change (an obstacle added or removed, a new tool shape) builds a new `CellCheck` from the arm's geometry in
about a millisecond; a check is one `pin.computeCollisions` call (about 20 us for six obstacles and two tool
capsules, against about 600 us for the former Python loop over coal pairs), a batch of configurations one
`pin.computeCollisionsInParallel` call.

Pairs checked: the arm's own (links that are not the same body nor parent and child; see collision.py),
every moving link and every tool capsule against the floor (z <= 0), and every obstacle against every moving
link and tool capsule. The base link is not checked against obstacles (it never moves), nor the tool against
the arm (it is mounted on it). `margin_m` pads the obstacles (not the floor, not the arm's own pairs): a
configuration closer than that to an obstacle counts as a collision (the planner's clearance).

The contact rule (contact.py) asks `touch`: per obstacle (and the floor, for the tool) the deepest
penetration (the signed distance of each touching pair, negated) and the links involved. It runs only where
the yes/no check found something touching, so a clear motion costs nothing more.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import coal
import numpy as np
import pinocchio as pin

from pendant.kinematics.arm_model import ArmModel, joint_vector
from pendant.kinematics.collision import FLOOR_NAME, UNIVERSE_JOINT, link_name
from pendant.kinematics.contact import FLOOR, Contact, Touch
from pendant.kinematics.obstacles import Capsule, capsule_shape

TOOL_PREFIX = "tool_capsule_"
TOOL_LINK = "tool"  # the link name the tool's capsules report in a contact
FLANGE_JOINT = "joint6"  # the tool's capsules ride on the last joint
# A half-space (the floor, a plane obstacle) is checked as a box this far from the plane's point nearest
# the base in every direction: more than the arm's reach plus the largest tool (2 m).
SLAB_HALF_M = 4.0
# Threads for a batch check: the machine's two cores (more only adds contention).
BATCH_THREADS = 2
# Below this many configurations a batch is checked on one thread (a second thread costs more than it saves).
MIN_PARALLEL_BATCH = 64


@dataclass(frozen=True)
class NamedShape:
    """An obstacle as coal geometry: its name, its shape and its pose T_base_shape (4, 4)."""

    name: str
    shape: coal.CollisionGeometry
    T: np.ndarray


@dataclass(frozen=True)
class Clearance:
    """The smallest distance (metres; negative: penetration depth) between the arm or its tool and an
    obstacle or the floor, and what it is measured to ("floor" or the obstacle's name)."""

    distance_m: float
    to: str


@dataclass(frozen=True)
class Approach:
    """How close one link (or the tool) comes to one obstacle: metres, signed (negative: penetration)."""

    distance_m: float
    link: str
    obstacle: str


def _se3(T: np.ndarray) -> pin.SE3:
    return pin.SE3(np.ascontiguousarray(T[:3, :3]), np.ascontiguousarray(T[:3, 3]))


def _joint_to_flange(arm: ArmModel, model: pin.Model, joint: int) -> np.ndarray:
    """T_joint_flange: the flange (the DH chain's end, where tool capsules are given) in the joint's frame;
    the same at every q, so taken at zero."""
    data = model.createData()
    q = np.zeros(model.nq)
    pin.forwardKinematics(model, data, q)
    return np.linalg.inv(data.oMi[joint].homogeneous) @ arm.fk(q)


class CellCheck:
    """The arm, its tool shape and the cell's obstacles; immutable (a change makes a new one).
    Thread-safe: every thread gets its own pinocchio scratch data."""

    def __init__(
        self,
        arm: ArmModel,
        obstacles: Sequence[NamedShape] = (),
        tool: Sequence[Capsule] = (),
        margin_m: float = 0.0,
    ) -> None:
        self.arm = arm
        self.obstacles = tuple(obstacles)
        self.tool = tuple(tool)
        self.margin_m = float(margin_m)
        pin_arm = arm.pin_arm
        self.model = pin_arm.model
        self._to_pin = pin_arm.to_pin
        geometry = pin_arm.collision.geometry_model.copy()
        objects = geometry.geometryObjects
        moving = [i for i in range(geometry.ngeoms) if objects[i].parentJoint != UNIVERSE_JOINT]
        floor = geometry.getGeometryId(FLOOR_NAME)
        floor_slab, T_floor = bounded(objects[floor].geometry, np.eye(4))
        objects[floor].geometry, objects[floor].placement = floor_slab, _se3(T_floor)
        flange_joint = self.model.getJointId(FLANGE_JOINT)
        T_joint_flange = _joint_to_flange(arm, self.model, flange_joint)
        tool_ids = []
        for k, capsule in enumerate(self.tool):
            shape, T_flange_shape = capsule_shape(capsule)
            placement = T_joint_flange @ T_flange_shape
            tool_ids.append(
                geometry.addGeometryObject(
                    pin.GeometryObject(f"{TOOL_PREFIX}{k}", flange_joint, _se3(placement), shape)
                )
            )
            geometry.addCollisionPair(pin.CollisionPair(tool_ids[-1], floor))
        self._obstacle_of_pair: dict[int, str] = {}
        self._padded_pairs: list[int] = []
        for obstacle in self.obstacles:
            shape, T = bounded(obstacle.shape, obstacle.T)
            obstacle_id = geometry.addGeometryObject(
                pin.GeometryObject(obstacle.name, UNIVERSE_JOINT, _se3(T), shape)
            )
            for other in (*moving, *tool_ids):
                geometry.addCollisionPair(pin.CollisionPair(other, obstacle_id))
                pair = geometry.findCollisionPair(pin.CollisionPair(other, obstacle_id))
                self._obstacle_of_pair[pair] = obstacle.name
                self._padded_pairs.append(pair)
        self._floor_pairs = [
            index for index, pair in enumerate(geometry.collisionPairs) if floor in (pair.first, pair.second)
        ]
        # For the contact rule: what each pair of an obstacle or of the tool with the floor weighs as
        # (FLOOR: the floor) and the link of its moving side.
        self._contact_of_pair: dict[int, tuple[str | None, str]] = {}
        for index, pair in enumerate(geometry.collisionPairs):
            mover = pair.second if objects[pair.first].parentJoint == UNIVERSE_JOINT else pair.first
            link = TOOL_LINK if mover in tool_ids else link_name(objects[mover].name)
            if index in self._obstacle_of_pair:
                self._contact_of_pair[index] = (self._obstacle_of_pair[index], link)
            elif floor in (pair.first, pair.second) and mover in tool_ids:
                self._contact_of_pair[index] = (FLOOR, link)
        self.geometry_model = geometry
        self._names = [o.name for o in geometry.geometryObjects]
        self._local = threading.local()
        self._pool: pin.BroadPhaseManagerPool_DynamicAABBTreeCollisionManager | None = None
        self._pool_lock = threading.Lock()

    # --- scratch data ---------------------------------------------------------------------------------

    def _new_geometry_data(self) -> pin.GeometryData:
        """Scratch data with the margin on the obstacles' pairs, placed at q = 0: a broad-phase manager
        builds its tree from the placements it is given (unset ones make boxes of garbage)."""
        data = pin.GeometryData(self.geometry_model)
        self._pad(data)
        q_zero = np.zeros(self.model.nq)
        pin.updateGeometryPlacements(self.model, self.model.createData(), self.geometry_model, data, q_zero)
        return data

    def _scratch(self) -> tuple[pin.Data, pin.GeometryData]:
        local = self._local
        if not hasattr(local, "data"):
            local.data = self.model.createData()
            local.geometry_data = self._new_geometry_data()
            # coal's dynamic AABB tree: only shapes whose boxes overlap reach the narrow phase.
            local.broad_phase = pin.BroadPhaseManager_DynamicAABBTreeCollisionManager(
                self.model, self.geometry_model, local.geometry_data
            )
        return local.data, local.geometry_data

    def _broad_phase(self) -> tuple[pin.Data, pin.BroadPhaseManager_DynamicAABBTreeCollisionManager]:
        data, _ = self._scratch()
        return data, self._local.broad_phase

    # --- queries --------------------------------------------------------------------------------------

    @property
    def empty(self) -> bool:
        """No obstacle and no tool shape: only the arm with itself and the floor."""
        return not self.obstacles and not self.tool

    def with_margin(self, margin_m: float) -> CellCheck:
        """The same cell with the obstacles padded by `margin_m`."""
        return CellCheck(self.arm, self.obstacles, self.tool, margin_m)

    def collides(self, q: np.ndarray) -> bool:
        """The arm touches itself, the floor or an obstacle, or the tool the floor or an obstacle, at q."""
        q = np.asarray(q, dtype=float)
        # The cheap form of joint_vector's check (a sum is NaN or infinite if any element is): hot path.
        if q.shape != (self.model.nq,) or not math.isfinite(float(q.sum())):
            joint_vector(q)  # raises the ValueError that says what is wrong
        data, broad_phase = self._broad_phase()
        return bool(pin.computeCollisions(self.model, data, broad_phase, self._to_pin(q), True))

    def collides_many(self, qs: np.ndarray) -> np.ndarray:
        """`collides` for each row of qs (n, 6), as a bool array (n,): one C++ call over the batch."""
        qs = np.asarray(qs, dtype=float).reshape(-1, self.model.nq)
        if not np.all(np.isfinite(qs)):
            raise ValueError("configurations must be finite")
        if len(qs) == 0:
            return np.zeros(0, dtype=bool)
        # A small batch on one thread (still one C++ call: a third cheaper than a Python loop of collides).
        threads = BATCH_THREADS if len(qs) >= MIN_PARALLEL_BATCH else 1
        q_batch = np.asfortranarray(np.array([self._to_pin(q) for q in qs]).T)
        with self._pool_lock:
            if self._pool is None:
                pool = pin.BroadPhaseManagerPool_DynamicAABBTreeCollisionManager(
                    self.model, self.geometry_model, BATCH_THREADS
                )
                pool.update(self._new_geometry_data())  # every manager of the pool gets the padded requests
                self._pool = pool
            return np.asarray(pin.computeCollisionsInParallel(threads, self._pool, q_batch, True), dtype=bool)

    def _pad(self, data: pin.GeometryData) -> None:
        for index in self._padded_pairs:
            data.collisionRequests[index].security_margin = self.margin_m
        for request in data.collisionRequests:
            request.num_max_contacts = 1
            # Without contacts, coal's GJK misses some deep overlaps (a capsule's end at a box's centre);
            # the contact (EPA) runs only once a pair is found touching.
            request.enable_contact = True

    def path_collides(self, q_from: np.ndarray, q_to: np.ndarray, step_rad: float) -> bool:
        """Any configuration on the straight joint path q_from -> q_to, sampled at most `step_rad` apart
        per joint (both ends included), collides."""
        return bool(np.any(self.collides_many(joint_samples(q_from, q_to, step_rad))))

    def touching(self, q: np.ndarray) -> list[str] | None:
        """What the arm or its tool touches at q: the obstacles' names ([] when only the arm itself or the
        floor), or None when nothing does."""
        data, geometry_data = self._scratch()
        q_pin = self._to_pin(joint_vector(q))
        if not pin.computeCollisions(self.model, data, self.geometry_model, geometry_data, q_pin, False):
            return None
        names: list[str] = []
        for index, name in self._obstacle_of_pair.items():
            if geometry_data.collisionResults[index].isCollision() and name not in names:
                names.append(name)
        return names

    def touch(self, q: np.ndarray) -> Touch:
        """What touches at q (the contact rule's query): the arm itself (its own pairs, a link in the floor)
        and, per obstacle (FLOOR: the tool in the floor), the deepest penetration and the links touching."""
        data, geometry_data = self._scratch()
        q_pin = self._to_pin(joint_vector(q))
        if not pin.computeCollisions(self.model, data, self.geometry_model, geometry_data, q_pin, False):
            return Touch(False, {})
        itself = False
        depths: dict[str | None, float] = {}
        links: dict[str | None, list[str]] = {}
        for index in range(len(self.geometry_model.collisionPairs)):
            if not geometry_data.collisionResults[index].isCollision():
                continue
            if index not in self._contact_of_pair:
                itself = True
                continue
            name, link = self._contact_of_pair[index]
            distance = pin.computeDistance(self.geometry_model, geometry_data, index).min_distance
            depths[name] = max(depths.get(name, 0.0), 0.0, -float(distance))
            if link not in links.setdefault(name, []):
                links[name].append(link)
        return Touch(itself, {name: Contact(depths[name], tuple(links[name])) for name in depths})

    def contacts(self, q: np.ndarray) -> dict[str | None, Contact]:
        """Every obstacle (and the floor, for the tool) touching the arm or its tool at q: how deep, which
        links; {} when none does."""
        return dict(self.touch(q).contacts)

    def colliding_pairs(self, q: np.ndarray) -> list[tuple[str, str]]:
        """The (shape, shape) name pairs in contact at q ("floor", obstacle names, "tool_capsule_k")."""
        data, geometry_data = self._scratch()
        pin.computeCollisions(
            self.model, data, self.geometry_model, geometry_data, self._to_pin(joint_vector(q)), False
        )
        return [
            (self._names[pair.first], self._names[pair.second])
            for index, pair in enumerate(self.geometry_model.collisionPairs)
            if geometry_data.collisionResults[index].isCollision()
        ]

    def clearance(self, q: np.ndarray, *, with_itself: bool = False) -> Clearance:
        """The smallest distance from the arm and its tool to the obstacles and the floor at q (signed:
        negative is a penetration depth), without the margin; `with_itself`: the arm's own pairs too."""
        pairs = (
            range(len(self.geometry_model.collisionPairs))
            if with_itself
            else (*self._obstacle_of_pair, *self._floor_pairs)
        )
        nearest = self._nearest_pair(q, pairs)
        return Clearance(np.inf, "") if nearest is None else Clearance(nearest[1], self._what(nearest[0]))

    def closest_obstacle(self, q: np.ndarray) -> Approach | None:
        """The arm's or tool's closest approach to an obstacle at q (signed, without the margin) and which
        link (TOOL_LINK for the tool) and obstacle; None in a cell without obstacles. (The pre-flight's.)"""
        nearest = self._nearest_pair(q, self._obstacle_of_pair)
        if nearest is None:
            return None
        index, distance = nearest
        return Approach(distance, self._contact_of_pair[index][1], self._obstacle_of_pair[index])

    def _nearest_pair(self, q: np.ndarray, pairs: Iterable[int]) -> tuple[int, float] | None:
        """Of the collision pairs `pairs`, the nearest at q and its signed distance; None for no pairs."""
        data, geometry_data = self._scratch()
        q_pin = self._to_pin(joint_vector(q))
        pin.updateGeometryPlacements(self.model, data, self.geometry_model, geometry_data, q_pin)
        best: tuple[int, float] | None = None
        for index in pairs:
            distance = float(pin.computeDistance(self.geometry_model, geometry_data, index).min_distance)
            if best is None or distance < best[1]:
                best = (index, distance)
        return best

    def _what(self, index: int) -> str:
        if index in self._obstacle_of_pair:
            return self._obstacle_of_pair[index]
        if index in self._floor_pairs:
            return FLOOR_NAME
        pair = self.geometry_model.collisionPairs[index]
        return f"{self._names[pair.first]} / {self._names[pair.second]}"


def bounded(shape: coal.CollisionGeometry, T: np.ndarray) -> tuple[coal.CollisionGeometry, np.ndarray]:
    """A half-space as a slab (a box) that holds all of it within SLAB_HALF_M of the base, so that the
    broad phase's bounding boxes stay finite (coal's AABB tree misses contacts with an infinite one); any
    other shape as it is."""
    if not isinstance(shape, coal.Halfspace):
        return shape, T
    normal = T[:3, :3] @ np.array(shape.n)
    offset = float(shape.d) + float(normal @ T[:3, 3])
    z = normal / np.linalg.norm(normal)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    T_slab = np.eye(4)
    T_slab[:3, :3] = np.column_stack([x, np.cross(z, x), z])
    T_slab[:3, 3] = z * (offset - SLAB_HALF_M)  # its top face is the plane, n . p = offset
    side = 2.0 * SLAB_HALF_M
    return coal.Box(side, side, side), T_slab


def joint_samples(q_from: np.ndarray, q_to: np.ndarray, step_rad: float) -> np.ndarray:
    """Configurations on the straight joint path from q_from to q_to, at most `step_rad` apart per joint,
    both ends included, shape (n, 6)."""
    q_from, q_to = joint_vector(q_from), joint_vector(q_to)
    steps = max(1, int(np.ceil(float(np.max(np.abs(q_to - q_from))) / step_rad)))
    return q_from + np.linspace(0.0, 1.0, steps + 1)[:, None] * (q_to - q_from)
