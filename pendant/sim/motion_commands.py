"""Motion commands on the simulator (mixed into SimController): plan outside the lock, queue under it.

Planning (IK, collision sampling: up to a second for a long LINEAR run) happens outside the lock, so a
freeze or a read never waits for it: the planner works from a snapshot of where the queue ends (`Start`),
and the plan is queued only if the queue still ends there, with the same tool, zero point and cell.
Otherwise something came in meanwhile (another command, a fault, a reset, a hand on the arm) and the plan is
made again from the new end. A freeze that came in while a command was being planned cancels it, as it
would have had the command been queued a moment earlier: the command is accepted and nothing moves.
"""

from __future__ import annotations

import math
import threading
from collections.abc import Callable

import numpy as np

from pendant.controller.errors import (
    MSG_GRIPPER_DISABLED,
    Collision,
    ControllerError,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import MotionParams, MotionType, Pose, Position
from pendant.sim.clock import paused
from pendant.sim.host import SimHost
from pendant.sim.io import GRIPPER_CLOSED, GRIPPER_OPEN
from pendant.sim.moves import (
    Start,
    Step,
    actions_of,
    blends_of,
    check_waypoint_count,
    plan_run,
    plan_to_configurations,
    plan_to_positions,
)
from pendant.sim.planner import Plan, check_params
from pendant.sim.states import Mode, check_can_move

# Transportation pose for PUT /pack: upper arm up, forearm folded down beside it, tool pointing down.
PACK_POSE_DEG = (0.0, -90.0, 150.0, -150.0, -90.0, 0.0)
PACK_SPEED_PERCENT = 20.0
# Where pack() goes first when the straight way to the transport pose is blocked (base angle kept).
UPRIGHT_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
# How often a plan is made again when the queue end keeps moving while it is planned (other clients).
MAX_PLAN_ATTEMPTS = 3
MSG_QUEUE_BUSY = (
    f"the command queue changed while the move was planned, {MAX_PLAN_ATTEMPTS} times: send it again"
)
# A waypoint's blend is metres at the TCP for positions, degrees of joint travel for poses; where a run
# moves in the other space, one radian of joint travel counts as this many metres of TCP travel.
BLEND_LEVER_M_PER_RAD = 0.5


class MotionCommands:
    """Moves, runs, gripper and pack: checked, planned from where the queue ends, then queued."""

    _lock: threading.RLock

    def _start(self: SimHost) -> Start:
        _, q0, _ = self._motions.end(self._now())
        frames = self._frames
        return Start(
            q0.copy(),
            frames.tool.radius,
            frames.T_flange_tool,
            frames.T_origbase_zero,
            self._freezes,
            self._environment.geometry,
        )

    def _starts_at(self: SimHost, start: Start) -> bool:
        """The queue still ends where `start` was read, with the same tool and zero point."""
        _, q0, _ = self._motions.end(self._now())
        frames = self._frames
        return (
            frames.T_flange_tool is start.T_flange_tool
            and frames.T_origbase_zero is start.T_origbase_zero
            and self._environment.geometry is start.cell
            and np.array_equal(q0, start.q)
        )

    def _plan_and_enqueue(
        self: SimHost, make_plan: Callable[[Start], list[Step] | None], jog: bool = False
    ) -> Position:
        """Plan outside the lock, queue under it; returns the TCP position when the command was accepted.

        A plan (or a refusal) made from a queue end that moved meanwhile is stale: plan again from there.
        Planning takes no simulated time on a scaled clock (`paused`).
        """
        with paused(self._clock):
            return self._plan_and_enqueue_now(make_plan, jog)

    def _plan_and_enqueue_now(
        self: SimHost, make_plan: Callable[[Start], list[Step] | None], jog: bool
    ) -> Position:
        for _ in range(MAX_PLAN_ATTEMPTS):
            with self._lock:
                check_can_move(self._mode)
                self._motions.check_room(self._now())
                start = self._start()
            try:
                plan = make_plan(start)
            except ControllerError:
                with self._lock:
                    if self._starts_at(start):
                        raise
                continue
            with self._lock:
                # A fault that came in meanwhile wins (500 / 503, nothing queued); so does a freeze.
                check_can_move(self._mode)
                if self._freezes != start.freezes:
                    return self._position_now()
                if self._starts_at(start):
                    self._motions.check_room(self._now(), len(plan) if plan else 1)
                    self._mode = Mode.ACTIVE  # a queued command engages the motors
                    if plan is None:
                        self._motions.append_plan(None, self._now())
                    for step in plan or []:
                        self._motions.append_plan(step.plan, self._now(), step.actions, jog)
                    return self._position_now()
        raise PreconditionFailed(MSG_QUEUE_BUSY)

    # --- motion --------------------------------------------------------------------------------------------

    # Planning runs without the lock (see the module doc): these methods take it only to read and to queue.

    def set_position(self: SimHost, position: Position, params: MotionParams) -> Position:
        """Queue a stop-at-target move to a TCP position; returns where the arm is when it is accepted."""
        return self._move_to_positions([position], params)

    def run_positions(self: SimHost, positions: list[Position], params: MotionParams) -> None:
        self._move_to_positions(positions, params)

    def set_pose(self: SimHost, pose: Pose, params: MotionParams) -> None:
        self._move_to_poses([pose], params)

    def run_poses(self: SimHost, poses: list[Pose], params: MotionParams) -> None:
        self._move_to_poses(poses, params)

    def _check_move(self: SimHost, params: MotionParams, waypoints: list[Pose] | list[Position]) -> None:
        with self._lock:
            check_can_move(self._mode)
            if not self._gripper_enabled and any(
                action.target == "gripper" for actions in actions_of(waypoints) for action in actions
            ):
                raise PreconditionFailed(MSG_GRIPPER_DISABLED)
        check_params(params)
        check_waypoint_count(len(waypoints))

    def _move_to_poses(self: SimHost, poses: list[Pose], params: MotionParams) -> None:
        """Through poses; each may carry a blend (degrees of joint travel) and actions."""
        self._check_move(params, poses)
        targets = [np.radians(pose.angles) for pose in poses]
        linear = params.motion_type is MotionType.LINEAR
        blends = blends_of(poses, np.radians(1.0) * (BLEND_LEVER_M_PER_RAD if linear else 1.0))
        planner, actions = self._planner, actions_of(poses)

        def plan_one(indices: list[int], start: Start) -> Plan:
            chosen = [blends[i] for i in indices] if blends else None
            return plan_to_configurations(planner, [targets[i] for i in indices], params, start, chosen)

        self._plan_and_enqueue(lambda start: plan_run(plan_one, len(targets), params, start, actions))

    def _move_to_positions(self: SimHost, positions: list[Position], params: MotionParams) -> Position:
        """Through positions; each may carry a blend (metres at the TCP) and actions."""
        self._check_move(params, positions)
        joint = params.motion_type is MotionType.JOINT
        blends = blends_of(positions, 1.0 / BLEND_LEVER_M_PER_RAD if joint else 1.0)
        planner, actions = self._planner, actions_of(positions)

        def plan_one(indices: list[int], start: Start) -> Plan:
            chosen = [blends[i] for i in indices] if blends else None
            return plan_to_positions(planner, [positions[i] for i in indices], params, start, chosen)

        return self._plan_and_enqueue(
            lambda start: plan_run(plan_one, len(positions), params, start, actions)
        )

    def open_gripper(self: SimHost, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_OPEN, timeout_ms)

    def close_gripper(self: SimHost, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_CLOSED, timeout_ms)

    def _gripper(self: SimHost, target: float, timeout_ms: float) -> None:
        check_can_move(self._mode)
        if not self._gripper_enabled:
            raise PreconditionFailed(MSG_GRIPPER_DISABLED)
        if not (math.isfinite(timeout_ms) and timeout_ms >= 0):
            raise PreconditionFailed(
                f"gripper timeout must be a number of milliseconds >= 0 (got {timeout_ms})"
            )
        now = self._now()
        self._motions.check_room(now)
        self._mode = Mode.ACTIVE
        self._motions.append_gripper(target, timeout_ms / 1000.0, now)

    def pack(self: SimHost) -> None:
        """Queue a JOINT move to the transportation pose PACK_POSE_DEG at PACK_SPEED_PERCENT, through the
        upright pose when the straight way is blocked. The reference lists no 412 for PUT /pack: with no
        clear way the command is accepted and fails when its turn comes (MOTION_FAILED, queue dropped)."""
        params = MotionParams(speed=PACK_SPEED_PERCENT)

        def plan(start: Start) -> list[Step] | None:
            for route in ([self._pack_q], [np.radians(UPRIGHT_DEG), self._pack_q]):
                try:
                    return [Step(plan_to_configurations(self._planner, route, params, start))]
                except (Collision, Unreachable):
                    continue
            return None

        self._plan_and_enqueue(plan)

    def busy_until(self: SimHost) -> float:
        """The clock time at which everything queued will be done (now, at rest)."""
        with self._lock:
            return self._motions.end(self._now())[0]
