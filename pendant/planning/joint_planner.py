"""Collision-free joint paths with OMPL (RRT-Connect and its path simplifier) over the ONE cell check.

The planner sees the world only through a `CellCheck` (the arm, its tool shape, the cell's obstacles, the
floor, itself) and the joint limits. It plans in joint space, each joint a real interval (a joint with
+-2*pi limits reaches the target as given, never an equivalent angle a turn away), with obstacles padded by
`MARGIN_M`, every edge checked at most `EDGE_STEP_RAD` apart per joint. The returned path is re-checked
every `RECHECK_STEP_RAD` per joint after simplification; one that fails is replaced by the unsimplified
path, or refused: a path that touches anything is never returned. A start where the arm touches an obstacle
(taken by the controller while the arm stood in it) is left first by a straight move under the contact rule
(escape.py), and planned from where that move ends.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
from ompl import base as ob
from ompl import geometric as og
from ompl import util as ou

from pendant.controller.errors import PreconditionFailed
from pendant.kinematics.cell_check import CellCheck, joint_samples
from pendant.planning.escape import ESCAPE_MAX_RAD, MSG_NO_WAY_OUT, leave_contact

MARGIN_M = 0.005  # obstacles are padded by this much while planning
EDGE_STEP_RAD = math.radians(1.0)  # an edge is checked at least this often per joint while planning
RECHECK_STEP_RAD = math.radians(0.5)  # and the returned path this often, after simplification
EDGE_FIRST_SINGLY = 6  # coarse samples of an edge checked one by one; the rest in one batch (C++)
# RRT-Connect's step: OMPL's own (a fifth of the +-2 pi space, 6 rad) made longer paths and as many checks.
RANGE_RAD = 1.0
DEFAULT_BUDGET_S = 1.0
MAX_BUDGET_S = 10.0
# The budget's shares: the search may use the first 60 %, the simplifier up to 85 %, and the rest is kept
# for the dense re-check, so that a plan ends within its budget.
SEARCH_SHARE = 0.6
SIMPLIFY_UNTIL = 0.85
MSG_NO_PATH = "no path found in {budget:g} s"
MSG_NO_CLEAR_PATH = "no path found that stays clear under the dense re-check"
MSG_CANCELLED = "the plan was cancelled"

Cancelled = Callable[[], bool]  # asked during the search: True ends it (Freeze pressed meanwhile)

ou.setLogLevel(ou.LogLevel.LOG_ERROR)  # OMPL's info lines ("Created 12 states") would flood the log


@dataclass(frozen=True)
class PlannedPath:
    """Joint waypoints (k, 6), radians: the start, the corners of the path, the target; and what it cost."""

    waypoints: np.ndarray
    planning_s: float
    margin_m: float

    @property
    def length_rad(self) -> float:
        """The path's length in joint space: the sum of its segments' Euclidean lengths."""
        return float(np.sum(np.linalg.norm(np.diff(self.waypoints, axis=0), axis=1)))


class PlanCancelled(PreconditionFailed):
    """The search was ended by its `cancelled` hook before it found a path."""


@dataclass(frozen=True)
class PlannerSettings:
    """How the search runs. `tuned=False` is OMPL's defaults (its default planner, its 1 % edge resolution,
    its default simplification, no straight-line try first, no dense re-check), for the benchmark's
    comparison: never for a path that is run."""

    margin_m: float = MARGIN_M
    tuned: bool = True
    range_rad: float = RANGE_RAD  # RRT-Connect's step; 0: OMPL's own (a fifth of the space's extent)
    cancelled: Cancelled | None = None  # polled by the search; True ends the plan (PlanCancelled)


def path_is_clear(check: CellCheck, waypoints: np.ndarray, step_rad: float = RECHECK_STEP_RAD) -> bool:
    """Every configuration along the straight joint segments between the waypoints, at most `step_rad`
    apart per joint, is collision-free."""
    samples = np.concatenate([joint_samples(a, b, step_rad) for a, b in itertools.pairwise(waypoints)])
    return not bool(np.any(check.collides_many(samples)))


def plan_joint_path(
    check: CellCheck,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    budget_s: float = DEFAULT_BUDGET_S,
    settings: PlannerSettings | None = None,
    cancelled: Cancelled | None = None,
) -> PlannedPath:
    """A collision-free joint path from q_start to q_goal, both inside the limits, q_goal clear and q_start
    clear or in a contact the rule lets it leave (the caller checks them and says why not).
    PreconditionFailed when no path is found within `budget_s`; PlanCancelled when `cancelled()` said so."""
    settings = settings or PlannerSettings()
    if cancelled is not None:
        settings = replace(settings, cancelled=cancelled)
    began = time.perf_counter()
    padded = check.with_margin(settings.margin_m) if settings.margin_m > 0.0 else check
    if check.collides(q_start):  # in contact: back out of it first, then plan from there
        q_exit = leave_contact(check, padded, q_start, q_goal, RECHECK_STEP_RAD)
        if q_exit is None:
            names = ", ".join(repr(name) for name in check.touching(q_start) or ()) or "something"
            raise PreconditionFailed(MSG_NO_WAY_OUT.format(names=names, limit=math.degrees(ESCAPE_MAX_RAD)))
        rest = _plan_clear(check, padded, q_exit, q_goal, began, budget_s, settings)
        return PlannedPath(np.vstack([q_start, rest.waypoints]), rest.planning_s, rest.margin_m)
    return _plan_clear(check, padded, q_start, q_goal, began, budget_s, settings)


def _plan_clear(
    check: CellCheck,
    padded: CellCheck,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    began: float,
    budget_s: float,
    settings: PlannerSettings,
) -> PlannedPath:
    """`plan_joint_path` between two clear ends, within the budget that began at `began`."""
    # An end already inside the margin (but clear) cannot be planned from padded: keep just clear instead.
    if padded is not check and (padded.collides(q_start) or padded.collides(q_goal)):
        padded = check
    straight = np.array([q_start, q_goal])
    if settings.tuned and path_is_clear(padded, straight, EDGE_STEP_RAD):
        return _checked(check, padded, straight, straight, began)
    raw, simplified = _search(padded, q_start, q_goal, began, budget_s, settings)
    if raw is None or simplified is None:
        raise PreconditionFailed(MSG_NO_PATH.format(budget=budget_s))
    if not settings.tuned:  # OMPL's answer as it is, for the benchmark to re-check
        return PlannedPath(simplified, time.perf_counter() - began, padded.margin_m)
    return _checked(check, padded, simplified, raw, began)


def _checked(
    check: CellCheck, padded: CellCheck, simplified: np.ndarray, raw: np.ndarray, began: float
) -> PlannedPath:
    """The simplified path if it passes the dense re-check, else the raw one, else a refusal. Padded
    first; a path clear only of the unpadded cell still touches nothing and is returned."""
    for candidate_check in (padded, check) if padded is not check else (check,):
        for waypoints in (simplified, raw):
            if path_is_clear(candidate_check, waypoints):
                return PlannedPath(waypoints, time.perf_counter() - began, candidate_check.margin_m)
    raise PreconditionFailed(MSG_NO_CLEAR_PATH)


def _search(
    check: CellCheck,
    q_start: np.ndarray,
    q_goal: np.ndarray,
    began: float,
    budget_s: float,
    settings: PlannerSettings,
) -> tuple[np.ndarray, np.ndarray] | tuple[None, None]:
    """OMPL's search: (the path as found, the path simplified), or Nones when none is found in time."""
    arm = check.arm
    space = ob.RealVectorStateSpace(len(q_start))
    bounds = ob.RealVectorBounds(len(q_start))
    for k, (low, high) in enumerate(zip(arm.lower, arm.upper, strict=True)):
        bounds.setLow(k, float(low))
        bounds.setHigh(k, float(high))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    dimension = len(q_start)

    def valid(state: ob.State) -> bool:
        return not check.collides(np.array([state[k] for k in range(dimension)]))

    setup.setStateValidityChecker(valid)
    information = setup.getSpaceInformation()
    if settings.tuned:
        validator = _EdgeValidator(information, check, dimension)
        information.setMotionValidator(validator)
        planner = og.RRTConnect(information)
        if settings.range_rad > 0.0:
            planner.setRange(settings.range_rad)
        setup.setPlanner(planner)
    start, goal = space.allocState(), space.allocState()
    for k in range(dimension):
        start[k], goal[k] = float(q_start[k]), float(q_goal[k])
    setup.setStartAndGoalStates(start, goal)
    search_s = max(0.0, began + SEARCH_SHARE * budget_s - time.perf_counter())
    if settings.cancelled is None:
        setup.solve(search_s)
    else:
        hook = settings.cancelled
        setup.solve(
            ob.plannerOrTerminationCondition(
                ob.PlannerTerminationCondition(lambda: bool(hook())),
                ob.timedPlannerTerminationCondition(search_s),
            )
        )
        if hook():
            raise PlanCancelled(MSG_CANCELLED)
    if not setup.haveExactSolutionPath():
        return None, None
    raw = _states(setup.getSolutionPath(), dimension)
    setup.simplifySolution(max(0.0, began + SIMPLIFY_UNTIL * budget_s - time.perf_counter()))
    return raw, _states(setup.getSolutionPath(), dimension)


class _EdgeValidator(ob.MotionValidator):
    """An edge is clear when its configurations at most EDGE_STEP_RAD apart per joint are (OMPL's own
    validator steps by Euclidean length, up to 2.4 times as many checks for the same per-joint step). Checked
    coarse to fine, so a blocked edge is usually found blocked after a few checks."""

    def __init__(self, information: ob.SpaceInformation, check: CellCheck, dimension: int) -> None:
        super().__init__(information)
        self._check = check
        self._dimension = dimension

    def checkMotion(self, s1: ob.State, s2: ob.State, *_last_valid: object) -> bool:
        a = np.array([s1[k] for k in range(self._dimension)])
        b = np.array([s2[k] for k in range(self._dimension)])
        steps = int(np.ceil(float(np.max(np.abs(b - a))) / EDGE_STEP_RAD))
        order = _coarse_to_fine(steps)
        collides = self._check.collides
        if any(collides(a + (k / steps) * (b - a)) for k in order[:EDGE_FIRST_SINGLY]):
            return False  # most blocked edges are found blocked here
        rest = np.array(order[EDGE_FIRST_SINGLY:], dtype=float)
        if len(rest) == 0:
            return True
        return not bool(np.any(self._check.collides_many(a + (rest / steps)[:, None] * (b - a))))


def _coarse_to_fine(steps: int) -> list[int]:
    """The inner sample indices 1..steps (the ends are valid states already), halving strides: a blocked
    middle is found first."""
    order: list[int] = []
    seen = {0}
    stride = 1 << max(0, steps.bit_length())
    while stride >= 1:
        for k in range(stride, steps + 1, stride):
            if k not in seen:
                seen.add(k)
                order.append(k)
        stride //= 2
    return order


def _states(path: og.PathGeometric, dimension: int) -> np.ndarray:
    return np.array(
        [[path.getState(i)[k] for k in range(dimension)] for i in range(path.getStateCount())], dtype=float
    )
