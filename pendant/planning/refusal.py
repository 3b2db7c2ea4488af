"""Why the twin refused a move, in the operator's words: what would hit what, which joint limit, where.

The controller answers a refused move with a short message ("Collision detected", "Unreachable Position").
The twin's planner is the simulator's own, instrumented: when it refuses, it keeps where along the move the
problem is and at which configuration, and `explain` turns that into a sentence such as
"the tool would hit 'fixture' at 62 % of the move".
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum

import numpy as np
from pydantic import BaseModel

from pendant.controller.errors import Collision, Unreachable
from pendant.controller.types import MotionParams
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.collision import FLOOR_NAME
from pendant.planning.clearance import TOOL_NAME, Clearance, part_name
from pendant.sim.paths import CartesianPath
from pendant.sim.planner import FLOOR_Z_M, Plan, Planner

# A straight line is probed at this many points to say where it leaves the reach or meets a singularity.
LINE_PROBES = 200
# Between two probes 1/200 of a line apart no joint turns this much unless IK changed branch.
BRANCH_JUMP_RAD = math.radians(20.0)


MAX_REMEMBERED_PLANS = 4096


def _key(value: object) -> object:
    """A hashable stand-in for a planner argument (arrays by value, models by their fields)."""
    if isinstance(value, np.ndarray):
        return (value.shape, value.tobytes())
    if isinstance(value, list | tuple):
        return tuple(_key(item) for item in value)
    if isinstance(value, dict):
        return tuple(sorted((name, _key(item)) for name, item in value.items()))
    if isinstance(value, BaseModel):
        return repr(value)
    return value  # floats, strings, None, a CellCheck (by identity: a cell change makes a new one)


class Problem(StrEnum):
    COLLISION = "collision"
    JOINT_LIMIT = "joint limit"
    OUT_OF_REACH = "unreachable"
    SINGULAR = "singular"


@dataclass(frozen=True)
class Refusal:
    """Where and why the last planned move was refused. `fraction`: 0..1 along the move, when known."""

    problem: Problem
    fraction: float | None = None
    q: np.ndarray | None = None  # the configuration that collides
    joint: int | None = None  # 0-based, for a joint limit
    tool_below_floor: bool = False


class DiagnosingPlanner(Planner):
    """The simulator's planner, remembering in `last` why its last refused move was refused.

    Plans are also remembered by their inputs: a loop's passes repeat the same moves from the same places,
    and planning them again (the collision checks) would cost most of a pre-flight's time."""

    def __init__(self, arm: ArmModel) -> None:
        super().__init__(arm)
        self.last: Refusal | None = None
        self._plans: dict[tuple[object, ...], Plan] = {}

    def _remembered(self, key: tuple[object, ...], plan: Callable[[], Plan]) -> Plan:
        found = self._plans.get(key)
        if found is None:
            found = plan()
            if len(self._plans) < MAX_REMEMBERED_PLANS:
                self._plans[key] = found
        return found

    def joint(
        self,
        q_start: np.ndarray,
        targets: list[np.ndarray],
        params: MotionParams,
        T_flange_tool: np.ndarray,
        tool_radius: float,
        unreachable_message: str,
        cell: CellCheck | None = None,
        blends_rad: list[float] | None = None,
    ) -> Plan:
        self.last = None
        inputs = (q_start, targets, params, T_flange_tool, tool_radius, unreachable_message, cell, blends_rad)
        try:
            return self._remembered(
                ("joint", *map(_key, inputs)), lambda: super(DiagnosingPlanner, self).joint(*inputs)
            )
        except Unreachable:
            if self.last is None:
                self.last = self._limits(targets) or Refusal(Problem.JOINT_LIMIT)
            raise

    def linear(
        self,
        q_start: np.ndarray,
        tcp_targets: list[np.ndarray],
        params: MotionParams,
        T_flange_tool: np.ndarray,
        tool_radius: float,
        unreachable_message: str,
        q_final: np.ndarray | None = None,
        cell: CellCheck | None = None,
        blends_m: list[float] | None = None,
    ) -> Plan:
        self.last = None
        inputs = (
            q_start,
            tcp_targets,
            params,
            T_flange_tool,
            tool_radius,
            unreachable_message,
            q_final,
            cell,
            blends_m,
        )
        try:
            return self._remembered(
                ("linear", *map(_key, inputs)), lambda: super(DiagnosingPlanner, self).linear(*inputs)
            )
        except Unreachable:
            if self.last is None:
                self.last = self._line_problem(q_start, tcp_targets, T_flange_tool)
            raise

    def note_limits(self, targets: list[np.ndarray]) -> None:
        """A command refused before planning: keep which target joint is past its limit, if one is."""
        if self.last is None:
            self.last = self._limits(targets)

    def _limits(self, targets: list[np.ndarray]) -> Refusal | None:
        for q in targets:
            outside = np.flatnonzero((q < self.arm.lower) | (q > self.arm.upper))
            if outside.size:
                return Refusal(Problem.JOINT_LIMIT, joint=int(outside[0]))
        return None

    def _line_problem(
        self, q_start: np.ndarray, tcp_targets: list[np.ndarray], T_flange_tool: np.ndarray
    ) -> Refusal:
        """Walk the straight line with IK, as the planner does, to find where it breaks."""
        T_tool_flange = np.linalg.inv(T_flange_tool)
        T_start = self.arm.fk(q_start) @ T_flange_tool
        path = CartesianPath([T_start, *tcp_targets])
        q = np.array(q_start, dtype=float)
        for k in range(1, LINE_PROBES + 1):
            fraction = k / LINE_PROBES
            found = self.arm.ik(path.pose(fraction * path.length) @ T_tool_flange, q)
            if found is None:
                return Refusal(Problem.OUT_OF_REACH, fraction)
            if float(np.max(np.abs(found - q))) > BRANCH_JUMP_RAD:
                return Refusal(Problem.SINGULAR, fraction)
            q = found
        return Refusal(Problem.SINGULAR)

    def _check_collisions(
        self, qs: np.ndarray, tcp: np.ndarray, tool_radius: float, cell: CellCheck | None = None
    ) -> None:
        try:
            super()._check_collisions(qs, tcp, tool_radius, cell)
        except Collision:
            self.last = self._first_collision(qs, tcp, tool_radius, cell)
            raise

    def _first_collision(
        self, qs: np.ndarray, tcp: np.ndarray, tool_radius: float, cell: CellCheck | None
    ) -> Refusal:
        travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(tcp, axis=0), axis=1))])
        if travelled[-1] < 1e-3:  # the TCP hardly moves (a wrist turn): measure the joints' travel
            steps = np.max(np.abs(np.diff(qs, axis=0)), axis=1)
            travelled = np.concatenate([[0.0], np.cumsum(steps)])
        total = max(float(travelled[-1]), 1e-12)
        for k in range(len(qs)):
            below = bool(tcp[k, 2] - tool_radius < FLOOR_Z_M)
            if below or self.arm.in_collision(qs[k]) or (cell is not None and cell.collides(qs[k])):
                return Refusal(Problem.COLLISION, float(travelled[k]) / total, qs[k], tool_below_floor=below)
        return Refusal(Problem.COLLISION)


@dataclass(frozen=True)
class Explanation:
    reason: str
    obstacle: str | None = None
    problem: Problem | None = None


def _where(fraction: float | None) -> str:
    return "" if fraction is None else f" at {round(100 * fraction)} % of the move"


def explain(refusal: Refusal | None, message: str, arm: ArmModel, clearance: Clearance) -> Explanation:
    """The refusal in words; without one (a refusal the planner did not see), the controller's message."""
    if refusal is None:
        return Explanation(_plain(message))
    where = _where(refusal.fraction)
    match refusal.problem:
        case Problem.JOINT_LIMIT:
            joint = "a joint" if refusal.joint is None else f"J{refusal.joint + 1}"
            return Explanation(f"{joint} would go past its limit{where}", problem=refusal.problem)
        case Problem.OUT_OF_REACH:
            return Explanation(f"the target is out of the arm's reach{where}", problem=refusal.problem)
        case Problem.SINGULAR:
            return Explanation(
                f"the straight line passes through a singularity{where} (the wrist or elbow would flip)",
                problem=refusal.problem,
            )
    return _collision(refusal, arm, clearance)


def _collision(refusal: Refusal, arm: ArmModel, clearance: Clearance) -> Explanation:
    where = _where(refusal.fraction)
    if refusal.q is None:
        return Explanation(f"collision{where}", problem=Problem.COLLISION)
    if refusal.tool_below_floor:
        return Explanation(f"the tool would go below the floor{where}", problem=Problem.COLLISION)
    if arm.in_collision(refusal.q):
        pairs = arm.colliding_pairs(refusal.q)
        for a, b in pairs:
            if FLOOR_NAME in (a, b):
                link = part_name(b if a == FLOOR_NAME else a)
                return Explanation(f"{link} would hit the floor{where}", problem=Problem.COLLISION)
        if pairs:
            a, b = pairs[0]
            return Explanation(
                f"the arm would hit itself ({part_name(a)} and {part_name(b)}){where}",
                problem=Problem.COLLISION,
            )
    closest = clearance(refusal.q)
    if closest is not None and closest.mm <= 1.0:
        return Explanation(
            f"{closest.link} would hit {closest.obstacle!r}{where}", closest.obstacle, Problem.COLLISION
        )
    return Explanation(f"{TOOL_NAME} would hit the floor{where}", problem=Problem.COLLISION)


def _plain(message: str) -> str:
    lowered = message.lower()
    if lowered.startswith("unreachable"):
        return "the target is out of the arm's reach (or only reachable past a joint limit)"
    if lowered.startswith("collision"):
        return "collision"
    return message
