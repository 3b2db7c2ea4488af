"""The cell's obstacles (by name) and the tool's shape, as SDK 1.8.4 sets them, and their collision geometry.

Every change makes a new `CellCheck`, so a plan made from an older one is stale (see controller.py).

An obstacle that touches the arm where it stands still is taken, as a controller takes it: the contact rule
(kinematics/contact.py) then lets the arm back out and refuses any motion deeper in. One that touches the arm
while it moves (where it is, or where its queued moves end) is refused: the queued moves would drive into
it. A tool or tool shape that would touch something more than the arm already does is refused (its capsules
ride on every motion).
"""

from __future__ import annotations

import numpy as np
from pydantic import BaseModel

from pendant.controller.cell_types import (
    MAX_OBSTACLES,
    MSG_NO_OBSTACLE,
    MSG_OBSTACLE_TOUCHES_ARM,
    MSG_SHAPE_TOUCHES,
    MSG_TOO_MANY_OBSTACLES,
    Obstacle,
    ToolShape,
)
from pendant.controller.errors import Collision, PreconditionFailed
from pendant.controller.types import Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.cell_shapes import cell_check
from pendant.kinematics.contact import ContactGuard, Worse, worse_contact

# Beyond these an obstacle or a tool capsule is a typing error (and overflows the geometry arithmetic).
MAX_OBSTACLE_EXTENT_M = 100.0
MAX_TOOL_EXTENT_M = 2.0
MSG_OBSTACLE_TOO_FAR = f"obstacle must lie within {MAX_OBSTACLE_EXTENT_M:g} m of the arm base"
MSG_TOOL_SHAPE_TOO_BIG = f"tool shape must lie within {MAX_TOOL_EXTENT_M:g} m of the flange"


def _numbers(value: object) -> list[float]:
    """Every number in a JSON-like value, nested (coordinates, sides, radii)."""
    if isinstance(value, bool):
        return []
    if isinstance(value, int | float):
        return [float(value)]
    if isinstance(value, dict):
        return [n for item in value.values() for n in _numbers(item)]
    if isinstance(value, list):
        return [n for item in value for n in _numbers(item)]
    return []


def _check_extent(model: BaseModel, limit: float, message: str) -> None:
    if any(abs(v) > limit for v in _numbers(model.model_dump())):
        raise PreconditionFailed(message)


class Environment:
    """Obstacles kept by name (insertion order), the tool shape, and the geometry built from them."""

    def __init__(self, arm: ArmModel, tool: Tool) -> None:
        self.arm = arm
        self.obstacles: dict[str, Obstacle] = {}
        self.tool_shape = ToolShape(shape=[])
        self._tool = tool
        self.geometry = self._build(self.obstacles, self.tool_shape, tool)

    def _build(self, obstacles: dict[str, Obstacle], shape: ToolShape, tool: Tool) -> CellCheck:
        return cell_check(self.arm, obstacles.values(), shape, tool)

    def get(self, name: str) -> Obstacle:
        try:
            return self.obstacles[name]
        except KeyError:
            raise PreconditionFailed(MSG_NO_OBSTACLE.format(name=name)) from None

    def add(self, obstacle: Obstacle, q_now: np.ndarray, q_end: np.ndarray) -> tuple[str, ...]:
        """Add (or replace, by name) an obstacle; returns the links it touches where the arm stands (none:
        clear of it). Refused if it touches the arm while the arm moves (now at q_now, its queue ending at
        q_end)."""
        if obstacle.name not in self.obstacles and len(self.obstacles) >= MAX_OBSTACLES:
            raise PreconditionFailed(MSG_TOO_MANY_OBSTACLES)
        _check_extent(obstacle, MAX_OBSTACLE_EXTENT_M, MSG_OBSTACLE_TOO_FAR)
        obstacles = {**self.obstacles, obstacle.name: obstacle}
        geometry = self._build(obstacles, self.tool_shape, self._tool)
        contact = geometry.contacts(q_now).get(obstacle.name)
        moving = not np.array_equal(q_now, q_end)
        if moving and (contact is not None or obstacle.name in geometry.contacts(q_end)):
            raise Collision(MSG_OBSTACLE_TOUCHES_ARM)
        self.obstacles, self.geometry = obstacles, geometry
        return contact.links if contact is not None else ()

    def remove(self, name: str) -> None:
        self.get(name)
        self._commit({k: v for k, v in self.obstacles.items() if k != name}, self.tool_shape, self._tool)

    def clear(self) -> None:
        self._commit({}, self.tool_shape, self._tool)

    def check_tool(self, shape: ToolShape, tool: Tool, configurations: list[np.ndarray]) -> CellCheck:
        """The geometry with this tool shape and tool, or Collision if it touches anything already."""
        _check_extent(shape, MAX_TOOL_EXTENT_M, MSG_TOOL_SHAPE_TOO_BIG)
        geometry = self._build(self.obstacles, shape, tool)
        touching = geometry.collides_many(np.array(configurations))  # the depths only where touching
        for q, collides in zip(configurations, touching, strict=True):
            if collides and self._tool_touches_more(geometry, q):
                raise Collision(MSG_SHAPE_TOUCHES)
        return geometry

    def _tool_touches_more(self, geometry: CellCheck, q: np.ndarray) -> bool:
        """The new tool makes a contact at q: a new obstacle, a new link on one, or one deeper (an obstacle
        the arm already touches must not stop the tool from changing)."""
        before, after = self.geometry.contacts(q), geometry.contacts(q)
        depths = {name: contact.depth_m for name, contact in before.items()}
        if worse_contact(depths, {name: contact.depth_m for name, contact in after.items()}) is not None:
            return True
        return any(not set(c.links) <= set(before[name].links) for name, c in after.items())

    def move_check(self, q_from: np.ndarray, q_to: np.ndarray) -> Worse | None:
        """The contact rule for a jump from q_from to q_to (a hand moving the relaxed arm): None if q_to
        touches nothing new and nothing deeper."""
        return ContactGuard(self.geometry, q_from).check(q_to)

    def touching(self, q: np.ndarray) -> list[str] | None:
        """What the arm or its tool would touch at q: the obstacles' names ([] for the floor or the arm
        itself), or None when nothing is touched."""
        return self.geometry.touching(q)

    def set_tool(self, shape: ToolShape, tool: Tool, geometry: CellCheck) -> None:
        self.tool_shape, self._tool, self.geometry = shape, tool, geometry

    def _commit(self, obstacles: dict[str, Obstacle], shape: ToolShape, tool: Tool) -> None:
        geometry = self._build(obstacles, shape, tool)
        self.obstacles, self.tool_shape, self._tool, self.geometry = obstacles, shape, tool, geometry
