"""Turn a motion command into a checked, time-parameterised joint trajectory (or refuse it).

Everything here is a pure function of its inputs: the arm model, the configuration the arm will be in when
the command starts, the tool, and the motion parameters. Nothing moves until a plan comes back.
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections import deque
from dataclasses import dataclass

import numpy as np

from pendant.controller.errors import MSG_COLLISION, Collision, PreconditionFailed, Unreachable
from pendant.controller.types import (
    ACCELERATION_MAX,
    SPEED_MAX,
    SPEED_MIN,
    TCP_MAX_VELOCITY_MAX,
    TCP_MAX_VELOCITY_MIN,
    InterpolationType,
    MotionParams,
)
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck
from pendant.kinematics.collision_words import contact_words
from pendant.kinematics.contact import ContactGuard
from pendant.kinematics.limits import JOINT_MAX_ACCEL_RAD_S2, JOINT_MAX_SPEED_RAD_S
from pendant.kinematics.transforms import inverse
from pendant.sim import profile
from pendant.sim.curves import SampledJointPath, SplineJointPath
from pendant.sim.paths import CartesianPath, JointPath
from pendant.sim.profile import TimeScaling

# Collision checks along a path: at least every 2 degrees of the leading joint and every 5 mm of TCP travel.
CHECK_JOINT_STEP_RAD = math.radians(2.0)
CHECK_TCP_STEP_M = 0.005
# A LINEAR path is sampled every 1.5 mm of s (<= 1.5 mm of TCP travel, <= 0.43 degrees of TCP turn) and
# refined where a joint moves more than 1 degree between samples; if a joint still jumps by more than that
# over 1 micrometre of path, IK has changed branch (or crossed a singularity) and the path is refused.
LINEAR_SAMPLE_STEP_M = 0.0015
LINEAR_JOINT_STEP_RAD = math.radians(1.0)
LINEAR_MIN_STEP_M = 1e-6
# A LINEAR move to a pose must arrive in that very configuration, not another IK branch of the same TCP pose.
POSE_MATCH_TOL_RAD = 1e-4
# The TCP speed cap is planned with this much margin, for the speed change inside a sampling cell.
TCP_CAP_MARGIN = 0.98
FLOOR_Z_M = 0.0
MAX_TCP_REFINE = 64
# A LINEAR SPLINE run rounds every corner as far as its segments allow (blends are capped at half of each).
LINEAR_SPLINE_BLEND_M = 10.0


@dataclass(frozen=True)
class Plan:
    """A checked trajectory: the joint path, its time scaling and where it ends."""

    path: JointPath | SplineJointPath | SampledJointPath
    scaling: TimeScaling
    q_end: np.ndarray
    waypoint_s: tuple[float, ...] = ()  # where on the path (s) each target is reached (or blended past)

    def time_at(self, s: float) -> float:
        """Seconds after the start at which the path reaches s (the scaling's grid, linear in between)."""
        grid, times = self.scaling.s, self.scaling.t
        if len(grid) < 2 or s <= grid[0]:
            return 0.0
        k = bisect.bisect_left(grid, s)
        if k >= len(grid):
            return times[-1]
        s0, s1 = grid[k - 1], grid[k]
        return times[k - 1] + (times[k] - times[k - 1]) * ((s - s0) / (s1 - s0) if s1 > s0 else 1.0)

    @property
    def duration(self) -> float:
        return self.scaling.duration


# The SDK checks only "above 0"; below these a motion would take ages (or underflow to a standstill).
MIN_PERCENT = 0.01
MIN_TCP_VELOCITY_M_S = 1e-4
MIN_TCP_ACCELERATION_M_S2 = 1e-4


def check_params(params: MotionParams) -> None:
    """PreconditionFailed with a clear message when a parameter is out of its range."""
    floors = (
        ("speed", params.speed, MIN_PERCENT, "%"),
        ("acceleration", params.acceleration, MIN_PERCENT, "%"),
        ("tcp_max_velocity", params.tcp_max_velocity, MIN_TCP_VELOCITY_M_S, "m/s"),
        ("acceleration", params.tcp_acceleration, MIN_TCP_ACCELERATION_M_S2, "m/s^2"),
    )
    for name, value, floor, unit in floors:
        if value is not None and 0.0 < value < floor:
            raise PreconditionFailed(f"{name} must be at least {floor:g} {unit} (got {value:g})")
    if not (math.isfinite(params.speed) and SPEED_MIN < params.speed <= SPEED_MAX):
        raise PreconditionFailed(
            f"speed must be between {SPEED_MIN:g} (exclusive) and {SPEED_MAX:g} % (got {params.speed})"
        )
    tcp = params.tcp_max_velocity
    if not (math.isfinite(tcp) and TCP_MAX_VELOCITY_MIN < tcp <= TCP_MAX_VELOCITY_MAX):
        raise PreconditionFailed(
            f"tcp_max_velocity must be between {TCP_MAX_VELOCITY_MIN:g} (exclusive) and "
            f"{TCP_MAX_VELOCITY_MAX:g} m/s (got {tcp})"
        )
    acc = params.acceleration
    if acc is not None and not (math.isfinite(acc) and SPEED_MIN < acc <= ACCELERATION_MAX):
        raise PreconditionFailed(
            f"acceleration must be between {SPEED_MIN:g} (exclusive) and {ACCELERATION_MAX:g} % (got {acc})"
        )
    tcp_acc = params.tcp_acceleration
    if tcp_acc is not None and not (math.isfinite(tcp_acc) and tcp_acc > 0.0):
        raise PreconditionFailed(f"acceleration must be above 0 m/s^2 (got {tcp_acc})")


class Planner:
    """Plans JOINT and LINEAR motions for one arm, checking reach, joint limits and collisions."""

    def __init__(self, arm: ArmModel) -> None:
        self.arm = arm
        self.vmax = np.array(JOINT_MAX_SPEED_RAD_S, dtype=float)
        self.amax = np.array(JOINT_MAX_ACCEL_RAD_S2, dtype=float)

    # --- JOINT ---------------------------------------------------------------------------------------------

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
        """Joint-space motion from q_start to one target (a straight, synchronised move: all joints start
        and end together) or through several: a smooth spline through each of them, without stopping
        (SPLINE, the default), or straight segments with corners rounded within each target's blend
        (BLEND, or when a target has a blend)."""
        for q in targets:
            if not self.arm.within_limits(q):
                raise Unreachable(unreachable_message)
        waypoints = np.vstack([q_start, *targets])
        blended = params.interpolation is InterpolationType.BLEND or (
            params.interpolation is None and blends_rad is not None and any(blends_rad)
        )
        path: JointPath | SplineJointPath
        if len(targets) == 1 or blended:
            blends = None if blends_rad is None else [0.0, *blends_rad]
            path = JointPath(waypoints, self.vmax, blends_rad=blends)
        else:
            path = SplineJointPath(waypoints, self.vmax)
        marks = tuple(path.waypoint_s[1:])
        q_end = np.array(targets[-1], dtype=float)
        if path.length == 0.0:
            return Plan(path, profile.still(), q_end, marks)
        s_grid = path.grid(CHECK_JOINT_STEP_RAD / float(np.max(self.vmax)))
        qs = np.array([path.q(s) for s in s_grid])
        # A spline may bulge past a joint limit between waypoints that are inside.
        if np.any(qs < self.arm.lower) or np.any(qs > self.arm.upper):
            raise Unreachable(unreachable_message)
        qs[-1] = q_end
        tcp = self.tcp_points(qs, T_flange_tool)
        # Refine cells where the TCP travels more than the check step.
        chords = np.linalg.norm(np.diff(tcp, axis=0), axis=1)
        if np.any(chords > CHECK_TCP_STEP_M):
            pieces = [s_grid[:1]]
            for k, chord in enumerate(chords):
                # (capped: a tool metres long must not blow the grid up)
                n = min(MAX_TCP_REFINE, max(1, math.ceil(chord / CHECK_TCP_STEP_M)))
                pieces.append(np.linspace(s_grid[k], s_grid[k + 1], n + 1)[1:])
            s_grid = np.concatenate(pieces)
            qs = np.array([path.q(s) for s in s_grid])
            qs[-1] = q_end
            tcp = self.tcp_points(qs, T_flange_tool)
        self._check_collisions(qs, tcp, tool_radius, cell)
        # Derivatives at the cells' ends and middles: exact for straight moves (constant dq/ds, no curvature),
        # and close for the spline, whose dq/ds is quadratic and d2q/ds2 linear inside a cell.
        mids = 0.5 * (s_grid[:-1] + s_grid[1:])
        at_ends = [path.derivatives(float(s)) for s in s_grid]
        at_mids = [path.derivatives(float(s)) for s in mids]
        mid_d1 = np.array([d[1] for d in at_mids])
        mid_d2 = np.array([d[2] for d in at_mids])
        ends_d1 = np.abs(np.array([d[1] for d in at_ends]))
        ends_d2 = np.abs(np.array([d[2] for d in at_ends]))
        peak_d1 = np.maximum(np.maximum(ends_d1[:-1], ends_d1[1:]), np.abs(mid_d1))
        peak_d2 = np.maximum(np.maximum(ends_d2[:-1], ends_d2[1:]), np.abs(mid_d2))
        scaling = self._time_scaling(s_grid, mid_d1, mid_d2, tcp, params, peak_d1, peak_d2)
        return Plan(path, scaling, q_end, marks)

    # --- LINEAR --------------------------------------------------------------------------------------------

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
        """A straight TCP line (orientation slerped) from the current TCP through `tcp_targets` (T_base_tcp,
        original base frame), blended at the interior ones. With `q_final` the motion must end in that very
        configuration (a LINEAR move to a pose)."""
        T_tool_flange = inverse(T_flange_tool)
        # Every waypoint must be reachable at all before the line is sampled (and a far one is refused fast).
        for T_tcp in tcp_targets:
            if not np.all(np.isfinite(T_tcp)) or len(self.arm.ik_all(T_tcp @ T_tool_flange)) == 0:
                raise Unreachable(unreachable_message)
        T_start = self.arm.fk(q_start) @ T_flange_tool
        blends = None if blends_m is None else [0.0, *blends_m]
        if params.interpolation is InterpolationType.SPLINE:
            blends = [0.0] + [LINEAR_SPLINE_BLEND_M] * len(tcp_targets)  # as round as the segments allow
        path = CartesianPath([T_start, *tcp_targets], blends_m=blends)
        marks = tuple(path.waypoint_s[1:])
        if path.length == 0.0:
            q_end = q_start.copy() if q_final is None else np.array(q_final, dtype=float)
            if q_final is not None and np.max(np.abs(q_end - q_start)) > POSE_MATCH_TOL_RAD:
                raise Unreachable(unreachable_message)
            return Plan(SampledJointPath(np.array([0.0]), q_end[None, :]), profile.still(), q_end, marks)
        s_list, q_list, tcp_list = self._follow(path, q_start, T_tool_flange, unreachable_message)
        q_samples = np.array(q_list)
        if q_final is not None:
            if np.max(np.abs(q_samples[-1] - q_final)) > POSE_MATCH_TOL_RAD:
                raise Unreachable(unreachable_message)
            q_samples[-1] = q_final
        tcp = np.array(tcp_list)
        self._check_collisions(q_samples, tcp, tool_radius, cell)
        s_grid = np.array(s_list)
        sampled = SampledJointPath(s_grid, q_samples)
        slopes = sampled.slopes
        ddq = np.array([sampled.derivatives(float(0.5 * (a + b)))[2] for a, b in itertools.pairwise(s_grid)])
        scaling = self._time_scaling(s_grid, slopes, ddq, tcp, params)
        return Plan(sampled, scaling, q_samples[-1].copy(), marks)

    def _follow(
        self, path: CartesianPath, q_start: np.ndarray, T_tool_flange: np.ndarray, message: str
    ) -> tuple[list[float], list[np.ndarray], list[np.ndarray]]:
        """IK along the path, each sample on the branch nearest the previous one; refuse jumps."""
        s_list = [0.0]
        q_list = [np.array(q_start, dtype=float)]
        tcp_list = [path.pose(0.0)[:3, 3]]
        pending = deque(path.grid(LINEAR_SAMPLE_STEP_M)[1:].tolist())
        while pending:
            s = pending[0]
            T_tcp = path.pose(s)
            q = self.arm.ik(T_tcp @ T_tool_flange, q_list[-1])
            if q is None:
                raise Unreachable(message)
            step = float(np.max(np.abs(q - q_list[-1])))
            if step > LINEAR_JOINT_STEP_RAD:
                if s - s_list[-1] <= LINEAR_MIN_STEP_M:
                    raise Unreachable(message)  # a branch change or a singularity on the line
                pending.appendleft(0.5 * (s_list[-1] + s))
                continue
            pending.popleft()
            s_list.append(s)
            q_list.append(q)
            tcp_list.append(T_tcp[:3, 3])
        return s_list, q_list, tcp_list

    # --- shared --------------------------------------------------------------------------------------------

    def tcp_points(self, qs: np.ndarray, T_flange_tool: np.ndarray) -> np.ndarray:
        offset = T_flange_tool[:3, 3]
        out = np.empty((len(qs), 3))
        for k, q in enumerate(qs):
            T = self.arm.fk(q)
            out[k] = T[:3, 3] + T[:3, :3] @ offset
        return out

    def _check_collisions(
        self, qs: np.ndarray, tcp: np.ndarray, tool_radius: float, cell: CellCheck | None = None
    ) -> None:
        """Collision at the samples that are 2 degrees / 5 mm apart (and always at the last one): the arm
        with itself and the floor, and with the cell's obstacles and the tool's shape. An obstacle the arm
        already touches at the start may stay touched, no deeper (the contact rule, kinematics/contact.py)."""
        if np.any(tcp[:, 2] - tool_radius < FLOOR_Z_M):
            raise Collision()
        last_q, last_p = qs[0], tcp[0]
        n = len(qs)
        checked = []
        for k in range(1, n):
            far = (
                np.max(np.abs(qs[k] - last_q)) >= CHECK_JOINT_STEP_RAD
                or np.linalg.norm(tcp[k] - last_p) >= CHECK_TCP_STEP_M
            )
            if far or k == n - 1 or k == 1:
                checked.append(k)
                last_q, last_p = qs[k], tcp[k]
        if not checked:
            return
        if cell is None:
            if any(self.arm.in_collision(qs[k]) for k in checked):
                raise Collision()
            return
        touching = cell.collides_many(qs[checked])  # one C++ call for the whole path
        if not np.any(touching):
            return
        # Something touches: the contact rule, sample by sample in path order (depths only where touching).
        guard = ContactGuard(cell, qs[0])
        for k, collides in zip(checked, touching, strict=True):
            worse = guard.check(qs[k], bool(collides))
            if worse is not None:
                # The arm with itself: the bare words, the page names the two links (cell/collision_names.py).
                raise Collision(MSG_COLLISION if worse.itself else contact_words(worse))

    def _time_scaling(
        self,
        s_grid: np.ndarray,
        dq_ds: np.ndarray,
        ddq_ds2: np.ndarray,
        tcp: np.ndarray,
        params: MotionParams,
        dq_ds_peak: np.ndarray | None = None,
        ddq_ds2_peak: np.ndarray | None = None,
    ) -> TimeScaling:
        """Caps on ds/dt per cell (joint speeds, the turn of a curved path, the TCP cap) and the joint
        acceleration limits, for the cells' (signed) derivatives `dq_ds`, `ddq_ds2` (N, 6); the `_peak`
        arrays are each cell's largest magnitudes (default: the same)."""
        speed = params.speed / 100.0
        accel = (params.acceleration if params.acceleration is not None else params.speed) / 100.0
        accel_limit = accel * self.amax
        tiny = 1e-12
        peak_d1 = np.maximum(np.abs(dq_ds if dq_ds_peak is None else dq_ds_peak), tiny)
        peak_d2 = np.maximum(np.abs(ddq_ds2 if ddq_ds2_peak is None else ddq_ds2_peak), tiny)
        v_cap = np.min(speed * self.vmax / peak_d1, axis=1)
        # Where the path curves, |q''| s'^2 alone must fit in the acceleration limit.
        v_cap = np.minimum(v_cap, np.min(np.sqrt(accel_limit / peak_d2), axis=1))
        # TCP speed per unit s: chords, widened to the neighbouring cells for the change inside a cell.
        rate = np.linalg.norm(np.diff(tcp, axis=0), axis=1) / np.diff(s_grid)
        widened = rate.copy()
        widened[1:] = np.maximum(widened[1:], rate[:-1])
        widened[:-1] = np.maximum(widened[:-1], rate[1:])
        v_cap = np.minimum(v_cap, TCP_CAP_MARGIN * params.tcp_max_velocity / np.maximum(widened, tiny))
        if params.tcp_acceleration is not None:
            # The TCP as one more "joint": its speed along the path is rate * s', its acceleration
            # rate * s'' (the turn of a corner aside), capped like a joint's.
            dq_ds = np.column_stack([dq_ds, rate])
            ddq_ds2 = np.column_stack([ddq_ds2, np.zeros(len(rate))])
            accel_limit = np.append(accel_limit, params.tcp_acceleration)
        return profile.plan(s_grid, v_cap, dq_ds, ddq_ds2, accel_limit)
