"""SimController: the embedded PULSE controller simulator (implements `pendant.controller.Controller`).

State is a pure function of the commands received and the clock: every motion command is planned and
checked up front, then appended to a timeline (`timeline.Motion`) that is evaluated at `clock.now()` when
asked. There is no background thread and no busy loop; one re-entrant lock serialises callers (FastAPI and
viser call from different threads).

Planning (IK, collision sampling: up to a second for a long LINEAR run) happens outside the lock, so a
freeze or a read never waits for it: the planner works from a snapshot of where the queue ends (`_Start`),
and the plan is queued only if the queue still ends there, with the same tool and zero point. Otherwise
something came in meanwhile (another command, a fault, a reset, a hand on the arm) and the plan is made again
from the new end. A freeze that came in while a command was being planned cancels it, as it would have had
the command been queued a moment earlier: the command is accepted and nothing moves (Freeze always wins).

Frames. T_zero_tcp = inv(T_origbase_zero) @ fk(q) @ T_flange_tool, where
- T_origbase_zero is the zero point set by POST /base (its pose in the physical base frame), and
- T_flange_tool is the tool set by POST /tool, read as the pose of the new TCP relative to the flange (the
  original TCP). The reference calls the tool position the "distance from the arm's zero point to the new
  TCP"; every tool definition in practice (and the only reading under which a tool stays attached when the
  arm moves) is the offset from the flange, so that is what the simulator uses.
GET /position reports T_zero_tcp; PUT /position and /positions/run take targets in that same frame, so
`set_position(get_position())` does not move the arm.
"""

from __future__ import annotations

import functools
import math
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from pendant.controller.errors import (
    MSG_UNREACHABLE_POSE,
    MSG_UNREACHABLE_POSITION,
    BadRequest,
    Collision,
    ControllerError,
    Emergency,
    NotResponding,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.types import (
    INPUT_PORTS,
    OUTPUT_PORTS,
    MotionParams,
    MotionStatus,
    MotionType,
    MotorStatus,
    Point,
    Pose,
    Position,
    RecoverResult,
    Rotation,
    SignalLevel,
    Tool,
)
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import inverse, matrix_to_position, position_to_matrix
from pendant.sim.clock import Clock, MonotonicClock
from pendant.sim.motors import ServoModel, servo_ids
from pendant.sim.planner import FLOOR_Z_M, Plan, Planner, check_params
from pendant.sim.timeline import Motion

# Power-on pose: upper arm up, forearm forward, tool pointing straight down (degrees, base first). Chosen
# clear of the wrist singularity (q5 = 0) and of the roll/pitch/yaw gimbal lock (pitch = +-90 degrees).
HOME_POSE_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)
# Transportation pose for PUT /pack: upper arm up, forearm folded down beside it, tool pointing down.
PACK_POSE_DEG = (0.0, -90.0, 150.0, -150.0, -90.0, 0.0)
PACK_SPEED_PERCENT = 20.0
# Where pack() goes first when the straight way to the transport pose is blocked (base angle kept).
UPRIGHT_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
DEFAULT_TOOL = Tool(
    name="flange",
    point=Point(x=0.0, y=0.0, z=0.0),
    rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
    radius=0.0,
)
DEFAULT_BASE = Position(point=Point(x=0.0, y=0.0, z=0.0), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0))
# Offsets beyond these are typing errors, not tools or cells (and would overflow the frame arithmetic).
MAX_TOOL_OFFSET_M = 2.0
MAX_BASE_OFFSET_M = 100.0
MSG_TOOL_TOO_BIG = f"Tool offset and radius must be within {MAX_TOOL_OFFSET_M:g} m of the flange"
MSG_BASE_TOO_FAR = f"Zero point must be within {MAX_BASE_OFFSET_M:g} m of the arm base"
GRIPPER_OPEN, GRIPPER_CLOSED = 1.0, 0.0
POWER_ON_GRIPPER = GRIPPER_OPEN
MSG_HAND_NEEDS_RELAX = "The arm can be moved by hand only in ZERO_GRAVITY: relax it first (PUT /relax)"
# A run is planned in one go before it is accepted (100 LINEAR waypoints 15 cm apart take most of a second),
# and a queue longer than anyone can follow is a runaway client, not a program: both are capped.
MAX_WAYPOINTS = 100
MAX_QUEUED_COMMANDS = 100
# How often a plan is made again when the queue end keeps moving while it is planned (other clients).
MAX_PLAN_ATTEMPTS = 3
MSG_QUEUE_BUSY = (
    f"the command queue changed while the move was planned, {MAX_PLAN_ATTEMPTS} times: send it again"
)
OVERHEAT_STATOR_C = 110.0  # PUT /sim/fault/overheat
# Finished motions kept for the thermal model before they are folded in (bounds memory if nobody reads).
_HISTORY_LIMIT = 256


class Fault(StrEnum):
    """Faults the simulator can be told to have (served under /sim/fault)."""

    ERROR = "ERROR"  # recoverable: the arm freezes in place; PUT /recover clears it
    EMERGENCY = "EMERGENCY"  # fatal: every call answers 503 until reset()
    NO_RESPONSE = "NO_RESPONSE"  # the controller hangs: every call answers 500 until reset()
    MOTION_FAILED = "MOTION_FAILED"  # the running motion fails mid-way: the arm stops, the queue empties


class _Mode(StrEnum):
    ACTIVE = "ACTIVE"  # motors engaged: IDLE or RUNNING, depending on the queue
    ZERO_GRAVITY = "ZERO_GRAVITY"
    MOTION_FAILED = "MOTION_FAILED"
    ERROR = "ERROR"
    EMERGENCY = "EMERGENCY"
    NO_RESPONSE = "NO_RESPONSE"


@functools.cache
def _load_arm(model: str) -> ArmModel:
    # One ArmModel per model per process: loading parses the URDF and builds the collision model.
    return ArmModel.load(model)


def _pose_of(q: np.ndarray) -> Pose:
    return Pose(angles=np.degrees(q).tolist())


def _check_waypoint_count(count: int) -> None:
    if count == 0:
        raise BadRequest()
    if count > MAX_WAYPOINTS:
        raise PreconditionFailed(f"waypoints must be 1 to {MAX_WAYPOINTS} per run (got {count})")


@dataclass(frozen=True)
class _Start:
    """What a plan is made from, read under the lock: where the queue ends, the tool and the zero point."""

    q: np.ndarray
    tool_radius: float
    T_flange_tool: np.ndarray
    T_origbase_zero: np.ndarray
    freezes: int  # freezes so far: one more by the time the plan is made means "cancelled"


class SimController:
    """A simulated PULSE controller: every `Controller` method, plus simulator-only controls."""

    def __init__(self, model: str = "pulse75", clock: Clock | None = None) -> None:
        self._lock = threading.RLock()
        self._clock: Clock = clock if clock is not None else MonotonicClock()
        self.arm: ArmModel = _load_arm(model)
        self._planner = Planner(self.arm)
        self._servos = ServoModel(self.arm.inverse_dynamics, self._clock.now())
        self._robot_id = "".join(servo_ids(self.arm.name))
        self._home_q = np.radians(HOME_POSE_DEG)
        self._pack_q = np.radians(PACK_POSE_DEG)
        self._freezes = 0  # freezes and resets so far: one more while a command is planned cancels it
        self._power_on()

    # --- state ---------------------------------------------------------------------------------------------

    def _power_on(self) -> None:
        now = self._clock.now()
        self._mode = _Mode.ACTIVE
        self._freezes += 1  # a reset cancels what is being planned too
        self._queue: deque[Motion] = deque()
        self._history: list[Motion] = []
        self._rest_q = self._home_q.copy()
        self._rest_gripper = POWER_ON_GRIPPER
        self._pose_cache: Pose | None = None
        self._outputs = dict.fromkeys(OUTPUT_PORTS, SignalLevel.LOW)
        self._inputs = dict.fromkeys(INPUT_PORTS, SignalLevel.LOW)
        self._apply_tool(DEFAULT_TOOL)
        self._apply_base(DEFAULT_BASE)
        self._servos.reset(now)
        self._thermal_q = self._rest_q.copy()

    def _settle(self, now: float) -> Motion | None:
        """Retire the motions finished by `now`; the motion running at `now`, or None at rest."""
        queue = self._queue
        while queue:
            head = queue[0]
            if head.fails and head.t0 <= now:
                # Its turn came and it cannot run: the arm stays, the rest of the queue is dropped.
                queue.clear()
                self._mode = _Mode.MOTION_FAILED
                self._pose_cache = None
                break
            if head.t_end > now:
                break
            done = queue.popleft()
            self._rest_q = done.q_end
            self._rest_gripper = done.gripper_end
            self._history.append(done)
            self._pose_cache = None
        if len(self._history) > _HISTORY_LIMIT:
            self._integrate_thermal(now)
        return queue[0] if queue else None

    def _q_now(self, now: float) -> np.ndarray:
        motion = self._settle(now)
        return self._rest_q if motion is None else motion.q_at(now)

    def _stop(self, now: float) -> None:
        """Stop dead where the arm is (freeze, relax, a fault) and forget the queued commands."""
        motion = self._settle(now)
        if motion is not None:
            cut = motion.cut(now)
            self._history.append(cut)
            self._rest_q = cut.q_end
            self._rest_gripper = cut.gripper_end
        self._queue.clear()
        self._pose_cache = None

    def _queue_end(self, now: float) -> tuple[float, np.ndarray, float]:
        """(time, joint angles, gripper opening) at which the next queued command will start."""
        self._settle(now)
        if self._queue:
            last = self._queue[-1]
            return last.t_end, last.q_end, last.gripper_end
        return now, self._rest_q, self._rest_gripper

    def check_alive(self) -> None:
        """Raise what every call answers in EMERGENCY (503) or when not responding (500)."""
        if self._mode is _Mode.EMERGENCY:
            raise Emergency()
        if self._mode is _Mode.NO_RESPONSE:
            raise NotResponding()

    def _check_can_move(self) -> None:
        self.check_alive()
        if self._mode is _Mode.ERROR:
            raise NotResponding()  # the reference's 500 text; GET /status/motion says ERROR

    def _check_queue_room(self) -> None:
        self._settle(self._clock.now())  # what is done is no longer queued
        queued = len(self._queue)
        if queued >= MAX_QUEUED_COMMANDS:
            raise PreconditionFailed(
                f"queue must hold at most {MAX_QUEUED_COMMANDS} commands (got {queued} queued): "
                "wait for the arm to work through them"
            )

    def _append(self, motion: Motion, now: float) -> None:
        # A queued command engages the motors: ZERO_GRAVITY and MOTION_FAILED end here.
        self._mode = _Mode.ACTIVE
        self._queue.append(motion)
        self._pose_cache = None
        self._settle(now)

    def _enqueue_plan(self, plan: Plan | None) -> None:
        """Queue a planned motion; None queues a command that fails when its turn comes (MOTION_FAILED)."""
        now = self._clock.now()
        t0, q0, g0 = self._queue_end(now)
        if plan is None:
            motion = Motion(t0=t0, duration=0.0, q_end=q0, gripper_start=g0, gripper_end=g0, fails=True)
        else:
            motion = Motion(
                t0=t0, duration=plan.duration, q_end=plan.q_end, gripper_start=g0, gripper_end=g0, plan=plan
            )
        self._append(motion, now)

    def _start(self) -> _Start:
        _, q0, _ = self._queue_end(self._clock.now())
        return _Start(q0.copy(), self._tool.radius, self._T_flange_tool, self._T_origbase_zero, self._freezes)

    def _starts_at(self, start: _Start) -> bool:
        """The queue still ends where `start` was read, with the same tool and zero point."""
        _, q0, _ = self._queue_end(self._clock.now())
        # _apply_tool and _apply_base make new matrices, so identity says "not changed since".
        return (
            self._T_flange_tool is start.T_flange_tool
            and self._T_origbase_zero is start.T_origbase_zero
            and np.array_equal(q0, start.q)
        )

    def _plan_and_enqueue(self, make_plan: Callable[[_Start], Plan | None]) -> Position:
        """Plan outside the lock, queue under it; returns the TCP position when the command was accepted.

        A plan (or a refusal) made from a queue end that moved meanwhile is stale: plan again from there.
        """
        for _ in range(MAX_PLAN_ATTEMPTS):
            with self._lock:
                self._check_can_move()
                self._check_queue_room()
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
                self._check_can_move()
                if self._freezes != start.freezes:
                    return self._position_now()
                if self._starts_at(start):
                    self._check_queue_room()
                    self._enqueue_plan(plan)
                    return self._position_now()
        raise PreconditionFailed(MSG_QUEUE_BUSY)

    def _integrate_thermal(self, now: float) -> None:
        """Fold the motion history up to `now` into the servo temperatures."""
        servos = self._servos
        q_hold = self._thermal_q
        for motion in [*self._history, *self._queue]:
            if motion.t0 >= now:
                break
            if motion.t_end <= servos.t:
                continue
            if motion.t0 > servos.t:
                self._hold(q_hold, motion.t0 - servos.t)
            servos.heat_along(motion.state_at, min(now, motion.t_end))
            q_hold = motion.q_at(servos.t)
        if servos.t < now:
            self._hold(q_hold, now - servos.t)
        self._thermal_q = q_hold
        self._history.clear()

    def _hold(self, q: np.ndarray, dt: float) -> None:
        zero = np.zeros(6)
        servos = self._servos
        servos.heat(servos.motor_current(servos.joint_torques(q, zero, zero)), dt)

    # --- frames and tool -----------------------------------------------------------------------------------

    def _apply_tool(self, tool: Tool) -> None:
        self._tool = tool
        self._T_flange_tool = position_to_matrix(tool.position)

    def _apply_base(self, base: Position) -> None:
        self._base = base
        self._T_origbase_zero = position_to_matrix(base)
        self._T_zero_origbase = inverse(self._T_origbase_zero)

    def _tcp_target(self, position: Position) -> np.ndarray:
        """T_origbase_tcp of a position given in the zero point frame."""
        return self._T_origbase_zero @ position_to_matrix(position)

    # --- reads ---------------------------------------------------------------------------------------------

    def get_position(self) -> Position:
        with self._lock:
            self.check_alive()
            return self._position_now()

    def _position_now(self) -> Position:
        q = self._q_now(self._clock.now())
        return matrix_to_position(self._T_zero_origbase @ self.arm.fk(q) @ self._T_flange_tool)

    def get_pose(self) -> Pose:
        with self._lock:
            self.check_alive()
            now = self._clock.now()
            motion = self._settle(now)
            if motion is not None:
                return _pose_of(motion.q_at(now))
            if self._pose_cache is None:
                self._pose_cache = _pose_of(self._rest_q)
            return self._pose_cache

    def get_motion_status(self) -> MotionStatus:
        with self._lock:
            self.check_alive()
            if self._mode is _Mode.ACTIVE:
                running = self._settle(self._clock.now()) is not None
                return MotionStatus.RUNNING if running else MotionStatus.IDLE
            return MotionStatus(self._mode.value)

    def get_motors(self) -> list[MotorStatus]:
        with self._lock:
            self.check_alive()
            now = self._clock.now()
            motion = self._settle(now)
            self._integrate_thermal(now)
            if motion is None:
                zero = np.zeros(6)
                return self._servos.status(self._rest_q, zero, zero)
            return self._servos.status(*motion.state_at(now))

    def get_tool(self) -> Tool:
        with self._lock:
            self.check_alive()
            return self._tool

    def get_base(self) -> Position:
        with self._lock:
            self.check_alive()
            return self._base

    def get_robot_id(self) -> str:
        with self._lock:
            self.check_alive()
            return self._robot_id

    def get_output(self, port: int) -> SignalLevel:
        with self._lock:
            self.check_alive()
            return self._outputs[_check_port(port, OUTPUT_PORTS, "output")]

    def get_input(self, port: int) -> SignalLevel:
        with self._lock:
            self.check_alive()
            return self._inputs[_check_port(port, INPUT_PORTS, "input")]

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
            self._check_can_move()
        check_params(params)
        _check_waypoint_count(waypoints)

    def _move_to_poses(self, poses: list[Pose], params: MotionParams) -> None:
        self._check_move(params, len(poses))
        targets = [np.radians(pose.angles) for pose in poses]
        self._plan_and_enqueue(lambda start: self._plan_to_configurations(targets, params, start))

    def _plan_to_configurations(self, targets: list[np.ndarray], params: MotionParams, start: _Start) -> Plan:
        for q in targets:
            if not self.arm.within_limits(q):
                raise Unreachable(MSG_UNREACHABLE_POSE)
        q0, tool, radius = start.q, start.T_flange_tool, start.tool_radius
        if params.motion_type is MotionType.JOINT:
            return self._planner.joint(q0, targets, params, tool, radius, MSG_UNREACHABLE_POSE)
        tcp = [self.arm.fk(q) @ tool for q in targets]
        return self._planner.linear(q0, tcp, params, tool, radius, MSG_UNREACHABLE_POSE, q_final=targets[-1])

    def _move_to_positions(self, positions: list[Position], params: MotionParams) -> Position:
        self._check_move(params, len(positions))
        return self._plan_and_enqueue(lambda start: self._plan_to_positions(positions, params, start))

    def _plan_to_positions(self, positions: list[Position], params: MotionParams, start: _Start) -> Plan:
        q0, tool, radius = start.q, start.T_flange_tool, start.tool_radius
        tcp_targets = [start.T_origbase_zero @ position_to_matrix(p) for p in positions]
        if params.motion_type is MotionType.LINEAR:
            return self._planner.linear(q0, tcp_targets, params, tool, radius, MSG_UNREACHABLE_POSITION)
        T_tool_flange = inverse(tool)
        configurations = []
        q_near = q0
        for T_tcp in tcp_targets:
            q = self.arm.ik(T_tcp @ T_tool_flange, q_near)
            if q is None:
                raise Unreachable(MSG_UNREACHABLE_POSITION)
            configurations.append(q)
            q_near = q
        return self._planner.joint(q0, configurations, params, tool, radius, MSG_UNREACHABLE_POSITION)

    def open_gripper(self, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_OPEN, timeout_ms)

    def close_gripper(self, timeout_ms: int) -> None:
        with self._lock:
            self._gripper(GRIPPER_CLOSED, timeout_ms)

    def _gripper(self, target: float, timeout_ms: int) -> None:
        self._check_can_move()
        if not (math.isfinite(timeout_ms) and timeout_ms >= 0):
            raise PreconditionFailed(
                f"gripper timeout must be a number of milliseconds >= 0 (got {timeout_ms})"
            )
        self._check_queue_room()
        now = self._clock.now()
        t0, q0, g0 = self._queue_end(now)
        duration = timeout_ms / 1000.0
        self._append(Motion(t0=t0, duration=duration, q_end=q0, gripper_start=g0, gripper_end=target), now)

    def pack(self) -> None:
        """Queue a JOINT move to the transportation pose PACK_POSE_DEG at PACK_SPEED_PERCENT, through the
        upright pose when the straight way is blocked. The reference lists no 412 for PUT /pack: with no
        clear way the command is accepted and fails when its turn comes (MOTION_FAILED, queue dropped)."""
        params = MotionParams(speed=PACK_SPEED_PERCENT)

        def plan(start: _Start) -> Plan | None:
            for route in ([self._pack_q], [np.radians(UPRIGHT_DEG), self._pack_q]):
                try:
                    return self._plan_to_configurations(route, params, start)
                except (Collision, Unreachable):
                    continue
            return None

        self._plan_and_enqueue(plan)

    def busy_until(self) -> float:
        """The clock time at which everything queued will be done (now, at rest)."""
        with self._lock:
            return self._queue_end(self._clock.now())[0]

    # --- state commands ------------------------------------------------------------------------------------

    def relax(self) -> None:
        """Stop where the arm is, drop the queue and go limp (ZERO_GRAVITY): move_by_hand() then moves it."""
        with self._lock:
            self._check_can_move()
            self._stop(self._clock.now())
            self._mode = _Mode.ZERO_GRAVITY

    def freeze(self) -> None:
        """Stop where the arm is, drop the queue and hold the position (IDLE). In ERROR it stays in ERROR."""
        with self._lock:
            self.check_alive()
            if self._mode is _Mode.ERROR:
                return
            self._freezes += 1  # cancels what is being planned (see the module doc)
            self._stop(self._clock.now())
            self._mode = _Mode.ACTIVE

    def recover(self) -> RecoverResult:
        """ERROR or MOTION_FAILED -> IDLE (SUCCESS); IDLE stays IDLE (SUCCESS); RUNNING and ZERO_GRAVITY:
        nothing to recover from (FAILED, nothing changes)."""
        with self._lock:
            self.check_alive()
            if self._mode in (_Mode.ERROR, _Mode.MOTION_FAILED):
                self._stop(self._clock.now())
                self._mode = _Mode.ACTIVE
                return RecoverResult.SUCCESS
            if self._mode is _Mode.ACTIVE and self._settle(self._clock.now()) is None:
                return RecoverResult.SUCCESS
            return RecoverResult.FAILED

    # --- IO and settings -----------------------------------------------------------------------------------

    def set_output(self, port: int, level: SignalLevel) -> None:
        with self._lock:
            self.check_alive()
            self._outputs[_check_port(port, OUTPUT_PORTS, "output")] = SignalLevel(level)

    def set_tool(self, tool: Tool) -> Tool:
        """Attach a tool: its point and rotation are the TCP pose relative to the flange (see module doc).
        Collision (412) when its sphere would reach below the floor now or where the queue ends."""
        with self._lock:
            self.check_alive()
            offset = max(abs(tool.point.x), abs(tool.point.y), abs(tool.point.z))
            if offset > MAX_TOOL_OFFSET_M or tool.radius > MAX_TOOL_OFFSET_M:
                raise PreconditionFailed(MSG_TOOL_TOO_BIG)
            # A tool already in the floor would make every later move fail its first collision check, so it
            # is refused where the arm is now and where the queued commands leave it.
            T_flange_tool = position_to_matrix(tool.position)
            now = self._clock.now()
            for q in (self._q_now(now), self._queue_end(now)[1]):
                if not self._tool_clears_floor(q, T_flange_tool, tool.radius):
                    raise Collision()
            self._apply_tool(tool)
            return self._tool

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
            if max(abs(base.point.x), abs(base.point.y), abs(base.point.z)) > MAX_BASE_OFFSET_M:
                raise PreconditionFailed(MSG_BASE_TOO_FAR)
            self._apply_base(base)
            return self._base

    # --- simulator-only controls ---------------------------------------------------------------------------

    def set_input(self, port: int, level: SignalLevel) -> None:
        """Drive a digital input (what a sensor wired to the control box would do)."""
        with self._lock:
            self._inputs[_check_port(port, INPUT_PORTS, "input")] = SignalLevel(level)

    def move_by_hand(self, pose: Pose) -> None:
        """Put the relaxed arm in `pose` as a hand would. Only in ZERO_GRAVITY; limits and collisions hold."""
        with self._lock:
            self.check_alive()
            if self._mode is not _Mode.ZERO_GRAVITY:
                raise PreconditionFailed(MSG_HAND_NEEDS_RELAX)
            q = np.radians(pose.angles)
            if not self.arm.within_limits(q):
                raise Unreachable(MSG_UNREACHABLE_POSE)
            if self.arm.in_collision(q):
                raise Collision()
            now = self._clock.now()
            self._integrate_thermal(now)
            self._rest_q = q
            self._thermal_q = q.copy()
            self._pose_cache = None

    def inject_fault(self, fault: Fault) -> None:
        """Make the controller fail: the arm stops dead where it is and the queue empties (see Fault)."""
        with self._lock:
            fault = Fault(fault)
            self._stop(self._clock.now())
            self._mode = _Mode(fault.value)

    def overheat(self, stator_c: float = OVERHEAT_STATOR_C) -> None:
        """The stator windings are suddenly this hot (a fault to test alarms on); they cool from there."""
        with self._lock:
            self._integrate_thermal(self._clock.now())
            self._servos.stator_c[:] = stator_c

    def reset(self) -> None:
        """Back to the power-on state: home pose, IDLE, IO low, default tool and base, cool servos."""
        with self._lock:
            self._power_on()

    def gripper_opening(self) -> float:
        """0 closed .. 1 open, at this instant (for the UI; answers in every state)."""
        with self._lock:
            now = self._clock.now()
            motion = self._settle(now)
            return self._rest_gripper if motion is None else motion.gripper_at(now)

    def joint_positions(self) -> np.ndarray:
        """Joint angles in radians at this instant (for the UI; answers in every state)."""
        with self._lock:
            return np.array(self._q_now(self._clock.now()))


def _check_port(port: int, ports: tuple[int, ...], kind: str) -> int:
    if port not in ports:
        choices = ", ".join(str(p) for p in ports[:-1]) + f" or {ports[-1]}"
        raise PreconditionFailed(f"{kind} port must be {choices} (got {port})")
    return port
