"""SimController: the embedded PULSE controller simulator (implements `pendant.controller.Controller`).

A thin facade over its parts: the state machine (states.py), the motion queue on the clock (queue.py), the
tool and zero point (cell.py), the planning of moves (moves.py, planner.py) and the IO board (io.py).

State is a pure function of the commands received and the clock: every motion command is planned and
checked up front, then appended to a timeline (`timeline.Motion`) that is evaluated at `clock.now()` when
asked. There is no background thread and no busy loop; one re-entrant lock serialises callers (FastAPI and
viser call from different threads).

Planning (IK, collision sampling: up to a second for a long LINEAR run) happens outside the lock, so a
freeze or a read never waits for it: the planner works from a snapshot of where the queue ends (`Start`),
and the plan is queued only if the queue still ends there, with the same tool and zero point. Otherwise
something came in meanwhile (another command, a fault, a reset, a hand on the arm) and the plan is made again
from the new end. A freeze that came in while a command was being planned cancels it, as it would have had
the command been queued a moment earlier: the command is accepted and nothing moves (Freeze always wins).

GET /position reports T_zero_tcp (cell.py); PUT /position and /positions/run take targets in that same frame,
so `set_position(get_position())` does not move the arm.
"""

from __future__ import annotations

import functools
import math
import threading
from collections.abc import Callable

import numpy as np

from pendant.controller.errors import (
    MSG_UNREACHABLE_POSE,
    Collision,
    ControllerError,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import (
    MotionParams,
    MotionStatus,
    MotorStatus,
    Pose,
    Position,
    RecoverResult,
    SignalLevel,
    Tool,
)
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim.cell import (
    DEFAULT_BASE,
    DEFAULT_TOOL,
    Frames,
    check_base_distance,
    check_tool_size,
)
from pendant.sim.clock import Clock, MonotonicClock, paused
from pendant.sim.io import GRIPPER_CLOSED, GRIPPER_OPEN, POWER_ON_GRIPPER, IOBoard
from pendant.sim.motors import ServoModel, servo_ids
from pendant.sim.moves import (
    MAX_WAYPOINTS,
    Start,
    check_waypoint_count,
    plan_to_configurations,
    plan_to_positions,
)
from pendant.sim.planner import FLOOR_Z_M, Plan, Planner, check_params
from pendant.sim.queue import MAX_QUEUED_COMMANDS, MotionQueue
from pendant.sim.states import Fault, Mode, check_alive, check_can_move
from pendant.sim.timeline import Motion

__all__ = [
    "DEFAULT_BASE",
    "DEFAULT_TOOL",
    "HOME_POSE_DEG",
    "MAX_QUEUED_COMMANDS",
    "MAX_WAYPOINTS",
    "MSG_QUEUE_BUSY",
    "PACK_POSE_DEG",
    "Fault",
    "SimController",
]

# Power-on pose: upper arm up, forearm forward, tool pointing straight down (degrees, base first). Chosen
# clear of the wrist singularity (q5 = 0) and of the roll/pitch/yaw gimbal lock (pitch = +-90 degrees).
HOME_POSE_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)
# Transportation pose for PUT /pack: upper arm up, forearm folded down beside it, tool pointing down.
PACK_POSE_DEG = (0.0, -90.0, 150.0, -150.0, -90.0, 0.0)
PACK_SPEED_PERCENT = 20.0
# Where pack() goes first when the straight way to the transport pose is blocked (base angle kept).
UPRIGHT_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
MSG_HAND_NEEDS_RELAX = "The arm can be moved by hand only in ZERO_GRAVITY: relax it first (PUT /relax)"
# How often a plan is made again when the queue end keeps moving while it is planned (other clients).
MAX_PLAN_ATTEMPTS = 3
MSG_QUEUE_BUSY = (
    f"the command queue changed while the move was planned, {MAX_PLAN_ATTEMPTS} times: send it again"
)
OVERHEAT_STATOR_C = 110.0  # PUT /sim/fault/overheat


@functools.cache
def _load_arm(model: str) -> ArmModel:
    # One ArmModel per model per process: loading parses the URDF and builds the collision model.
    return ArmModel.load(model)


class SimController:
    """A simulated PULSE controller: every `Controller` method, plus simulator-only controls."""

    def __init__(self, model: str = "pulse75", clock: Clock | None = None) -> None:
        self._lock = threading.RLock()
        self._clock: Clock = clock if clock is not None else MonotonicClock()
        self.arm: ArmModel = _load_arm(model)
        self._planner = Planner(self.arm)
        self._motions = MotionQueue(ServoModel(self.arm.inverse_dynamics, self._clock.now()), self._failed)
        self._robot_id = "".join(servo_ids(self.arm.name))
        self._home_q = np.radians(HOME_POSE_DEG)
        self._pack_q = np.radians(PACK_POSE_DEG)
        self._freezes = 0  # freezes and resets so far: one more while a command is planned cancels it
        self._power_on()

    # --- state ---------------------------------------------------------------------------------------------

    def _power_on(self) -> None:
        self._mode = Mode.ACTIVE
        self._freezes += 1  # a reset cancels what is being planned too
        self._motions.reset(self._home_q, POWER_ON_GRIPPER, self._clock.now())
        self._io = IOBoard()
        self._frames = Frames()

    def _failed(self) -> None:
        self._mode = Mode.MOTION_FAILED

    def _now(self) -> float:
        return self._clock.now()

    def check_alive(self) -> None:
        """Raise what every call answers in EMERGENCY (503) or when not responding (500)."""
        check_alive(self._mode)

    def _append_plan(self, plan: Plan | None) -> None:
        # A queued command engages the motors: ZERO_GRAVITY and MOTION_FAILED end here.
        self._mode = Mode.ACTIVE
        self._motions.append_plan(plan, self._now())

    def _start(self) -> Start:
        _, q0, _ = self._motions.end(self._now())
        frames = self._frames
        return Start(
            q0.copy(), frames.tool.radius, frames.T_flange_tool, frames.T_origbase_zero, self._freezes
        )

    def _starts_at(self, start: Start) -> bool:
        """The queue still ends where `start` was read, with the same tool and zero point."""
        _, q0, _ = self._motions.end(self._now())
        frames = self._frames
        return (
            frames.T_flange_tool is start.T_flange_tool
            and frames.T_origbase_zero is start.T_origbase_zero
            and np.array_equal(q0, start.q)
        )

    def _plan_and_enqueue(self, make_plan: Callable[[Start], Plan | None]) -> Position:
        """Plan outside the lock, queue under it; returns the TCP position when the command was accepted.

        A plan (or a refusal) made from a queue end that moved meanwhile is stale: plan again from there.
        Planning takes no simulated time on a scaled clock (`paused`).
        """
        with paused(self._clock):
            return self._plan_and_enqueue_now(make_plan)

    def _plan_and_enqueue_now(self, make_plan: Callable[[Start], Plan | None]) -> Position:
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
                    self._motions.check_room(self._now())
                    self._append_plan(plan)
                    return self._position_now()
        raise PreconditionFailed(MSG_QUEUE_BUSY)

    # --- reads ---------------------------------------------------------------------------------------------

    def get_position(self) -> Position:
        with self._lock:
            self.check_alive()
            return self._position_now()

    def _position_now(self) -> Position:
        return self._frames.position_of(self.arm, self._motions.q_now(self._now()))

    def get_pose(self) -> Pose:
        with self._lock:
            self.check_alive()
            return self._motions.pose_now(self._now())

    def get_motion_status(self) -> MotionStatus:
        with self._lock:
            self.check_alive()
            if self._mode is Mode.ACTIVE:
                running = self._motions.running(self._now())
                return MotionStatus.RUNNING if running else MotionStatus.IDLE
            return MotionStatus(self._mode.value)

    def get_motors(self) -> list[MotorStatus]:
        with self._lock:
            self.check_alive()
            return self._motions.motors(self._now())

    def get_tool(self) -> Tool:
        with self._lock:
            self.check_alive()
            return self._frames.tool

    def get_base(self) -> Position:
        with self._lock:
            self.check_alive()
            return self._frames.base

    def get_robot_id(self) -> str:
        with self._lock:
            self.check_alive()
            return self._robot_id

    def get_output(self, port: int) -> SignalLevel:
        with self._lock:
            self.check_alive()
            return self._io.output(port)

    def get_input(self, port: int) -> SignalLevel:
        with self._lock:
            self.check_alive()
            return self._io.input(port)

    # --- motion --------------------------------------------------------------------------------------------

    # Planning runs without the lock (see the module doc): these methods take it only to read and to queue.

    def set_position(self, position: Position, params: MotionParams) -> Position:
        """Queue a stop-at-target move to a TCP position; returns where the arm is when it is accepted."""
        return self._move_to_positions([position], params)

    def run_positions(self, positions: list[Position], params: MotionParams) -> None:
        self._move_to_positions(positions, params)

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self._move_to_poses([pose], params)

    def run_poses(self, poses: list[Pose], params: MotionParams) -> None:
        self._move_to_poses(poses, params)

    def _check_move(self, params: MotionParams, waypoints: int) -> None:
        with self._lock:
            check_can_move(self._mode)
        check_params(params)
        check_waypoint_count(waypoints)

    def _move_to_poses(self, poses: list[Pose], params: MotionParams) -> None:
        self._check_move(params, len(poses))
        targets = [np.radians(pose.angles) for pose in poses]
        self._plan_and_enqueue(lambda start: plan_to_configurations(self._planner, targets, params, start))

    def _move_to_positions(self, positions: list[Position], params: MotionParams) -> Position:
        self._check_move(params, len(positions))
        planner = self._planner
        return self._plan_and_enqueue(lambda start: plan_to_positions(planner, positions, params, start))

    def open_gripper(self, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_OPEN, timeout_ms)

    def close_gripper(self, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_CLOSED, timeout_ms)

    def _gripper(self, target: float, timeout_ms: float) -> None:
        check_can_move(self._mode)
        if not (math.isfinite(timeout_ms) and timeout_ms >= 0):
            raise PreconditionFailed(
                f"gripper timeout must be a number of milliseconds >= 0 (got {timeout_ms})"
            )
        now = self._now()
        self._motions.check_room(now)
        self._mode = Mode.ACTIVE
        self._motions.append_gripper(target, timeout_ms / 1000.0, now)

    def pack(self) -> None:
        """Queue a JOINT move to the transportation pose PACK_POSE_DEG at PACK_SPEED_PERCENT, through the
        upright pose when the straight way is blocked. The reference lists no 412 for PUT /pack: with no
        clear way the command is accepted and fails when its turn comes (MOTION_FAILED, queue dropped)."""
        params = MotionParams(speed=PACK_SPEED_PERCENT)

        def plan(start: Start) -> Plan | None:
            for route in ([self._pack_q], [np.radians(UPRIGHT_DEG), self._pack_q]):
                try:
                    return plan_to_configurations(self._planner, route, params, start)
                except (Collision, Unreachable):
                    continue
            return None

        self._plan_and_enqueue(plan)

    def busy_until(self) -> float:
        """The clock time at which everything queued will be done (now, at rest)."""
        with self._lock:
            return self._motions.end(self._now())[0]

    @property
    def clock(self) -> Clock:
        """The clock every time of the simulator is read from (GET /sim/clock, scripted events)."""
        return self._clock

    def queued_motions(self) -> tuple[Motion, ...]:
        """The queue as a timeline, the running command first (read-only, for scripted events)."""
        with self._lock:
            self._motions.settle(self._now())
            return tuple(self._motions.queue)

    # --- state commands ------------------------------------------------------------------------------------

    def relax(self) -> None:
        """Stop where the arm is, drop the queue and go limp (ZERO_GRAVITY): move_by_hand() then moves it."""
        with self._lock:
            check_can_move(self._mode)
            self._motions.stop(self._now())
            self._mode = Mode.ZERO_GRAVITY

    def freeze(self) -> None:
        """Stop where the arm is, drop the queue and hold the position (IDLE). In ERROR it stays in ERROR."""
        with self._lock:
            self.check_alive()
            if self._mode is Mode.ERROR:
                return
            self._freezes += 1  # cancels what is being planned (see the module doc)
            self._motions.stop(self._now())
            self._mode = Mode.ACTIVE

    def recover(self) -> RecoverResult:
        """ERROR or MOTION_FAILED -> IDLE (SUCCESS); IDLE stays IDLE (SUCCESS); RUNNING and ZERO_GRAVITY:
        nothing to recover from (FAILED, nothing changes)."""
        with self._lock:
            self.check_alive()
            if self._mode in (Mode.ERROR, Mode.MOTION_FAILED):
                self._motions.stop(self._now())
                self._mode = Mode.ACTIVE
                return RecoverResult.SUCCESS
            if self._mode is Mode.ACTIVE and not self._motions.running(self._now()):
                return RecoverResult.SUCCESS
            return RecoverResult.FAILED

    # --- IO and settings -----------------------------------------------------------------------------------

    def set_output(self, port: int, level: SignalLevel) -> None:
        with self._lock:
            self.check_alive()
            self._io.set_output(port, level)

    def set_tool(self, tool: Tool) -> Tool:
        """Attach a tool: its point and rotation are the TCP pose relative to the flange (see cell.py).
        Collision (412) when its sphere would reach below the floor now or where the queue ends."""
        with self._lock:
            self.check_alive()
            check_tool_size(tool)
            # A tool already in the floor would make every later move fail its first collision check, so it
            # is refused where the arm is now and where the queued commands leave it.
            T_flange_tool = position_to_matrix(tool.position)
            now = self._now()
            for q in (self._motions.q_now(now), self._motions.end(now)[1]):
                if not self._tool_clears_floor(q, T_flange_tool, tool.radius):
                    raise Collision()
            self._frames.apply_tool(tool)
            return self._frames.tool

    def _tool_clears_floor(self, q: np.ndarray, T_flange_tool: np.ndarray, radius: float) -> bool:
        """The planner's floor rule for one configuration: the tool sphere stays at or above the floor."""
        # The JOINT planner places the TCP with tcp_points, the LINEAR one with fk @ tool; both must pass,
        # so that rounding cannot make the first sample of a later move fail where set_tool saw none.
        heights = (
            float(self._planner.tcp_points(q[None, :], T_flange_tool)[0, 2]),
            float((self.arm.fk(q) @ T_flange_tool)[2, 3]),
        )
        return all(z - radius >= FLOOR_Z_M for z in heights)

    def set_base(self, base: Position) -> Position:
        """Move the zero point: `base` is its pose in the physical base frame."""
        with self._lock:
            self.check_alive()
            check_base_distance(base)
            self._frames.apply_base(base)
            return self._frames.base

    # --- simulator-only controls ---------------------------------------------------------------------------

    def set_input(self, port: int, level: SignalLevel) -> None:
        """Drive a digital input (what a sensor wired to the control box would do)."""
        with self._lock:
            self._io.set_input(port, level)

    def move_by_hand(self, pose: Pose) -> None:
        """Put the relaxed arm in `pose` as a hand would. Only in ZERO_GRAVITY; limits and collisions hold."""
        with self._lock:
            self.check_alive()
            if self._mode is not Mode.ZERO_GRAVITY:
                raise PreconditionFailed(MSG_HAND_NEEDS_RELAX)
            q = np.radians(pose.angles)
            if not self.arm.within_limits(q):
                raise Unreachable(MSG_UNREACHABLE_POSE)
            if self.arm.in_collision(q):
                raise Collision()
            self._motions.place(q, self._now())

    def inject_fault(self, fault: Fault) -> None:
        """Make the controller fail: the arm stops dead where it is and the queue empties (see Fault)."""
        with self._lock:
            fault = Fault(fault)
            self._motions.stop(self._now())
            self._mode = Mode(fault.value)

    def overheat(self, stator_c: float = OVERHEAT_STATOR_C) -> None:
        """The stator windings are suddenly this hot (a fault to test alarms on); they cool from there."""
        with self._lock:
            self._motions.integrate_thermal(self._now())
            self._motions.servos.stator_c[:] = stator_c

    def reset(self) -> None:
        """Back to the power-on state: home pose, IDLE, IO low, default tool and base, cool servos."""
        with self._lock:
            self._power_on()

    def gripper_opening(self) -> float:
        """0 closed .. 1 open, at this instant (for the UI; answers in every state)."""
        with self._lock:
            return self._motions.gripper_now(self._now())

    def joint_positions(self) -> np.ndarray:
        """Joint angles in radians at this instant (for the UI; answers in every state)."""
        with self._lock:
            return np.array(self._motions.q_now(self._now()))
