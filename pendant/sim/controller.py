"""SimController: the embedded PULSE controller simulator (implements `pendant.controller.Controller`).

A thin facade over its parts: the state machine (states.py), the motion queue on the clock (queue.py), the
tool and zero point (cell.py), the planning of moves (moves.py, planner.py) and the IO board (io.py).

State is a pure function of the commands received and the clock: every motion command is planned and
checked up front, then appended to a timeline (`timeline.Motion`) that is evaluated at `clock.now()` when
asked. There is no background thread and no busy loop; one re-entrant lock serialises callers (FastAPI and
viser call from different threads).

Motion commands are planned outside the lock (motion_commands.py); SDK 1.8.4's operations are in pulse18.py.

GET /position reports T_zero_tcp (cell.py); PUT /position and /positions/run take targets in that same frame,
so `set_position(get_position())` does not move the arm.
"""

from __future__ import annotations

import functools
import threading

import numpy as np

from pendant.controller.errors import (
    Collision,
)
from pendant.controller.system_types import FailureLevel, FailureType, OutputAction, RobotAction
from pendant.controller.types import (
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
from pendant.sim.clock import Clock, MonotonicClock
from pendant.sim.environment import Environment
from pendant.sim.failures import FailureLog
from pendant.sim.io import POWER_ON_GRIPPER, IOBoard
from pendant.sim.motion_commands import (
    MSG_QUEUE_BUSY,
    PACK_POSE_DEG,
    MotionCommands,
)
from pendant.sim.motors import ServoModel, servo_ids
from pendant.sim.moves import (
    MAX_WAYPOINTS,
)
from pendant.sim.planner import FLOOR_Z_M, Planner
from pendant.sim.pulse18 import Pulse18Operations
from pendant.sim.queue import MAX_QUEUED_COMMANDS, MotionQueue
from pendant.sim.sim_controls import SimOnlyControls
from pendant.sim.states import Fault, Mode, check_alive, check_can_move, motion_status
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


@functools.cache
def _load_arm(model: str) -> ArmModel:
    # One ArmModel per model per process: loading parses the URDF and builds the collision model.
    return ArmModel.load(model)


class SimController(MotionCommands, Pulse18Operations, SimOnlyControls):
    """A simulated PULSE controller: every `Controller` method, plus simulator-only controls."""

    def __init__(
        self, model: str = "pulse75", clock: Clock | None = None, epoch: float | None = None
    ) -> None:
        """`epoch`: the Unix time at which `clock` read 0, for timestamps; default: the clock's own."""
        self._lock = threading.RLock()
        self._clock: Clock = clock if clock is not None else MonotonicClock()
        self._epoch = epoch
        self.model = model
        self.arm: ArmModel = _load_arm(model)
        self._planner = Planner(self.arm)
        self._failures = FailureLog(self.clock_time)
        servos = ServoModel(self.arm.inverse_dynamics, self._clock.now())
        self._motions = MotionQueue(servos, self._failed, self._run_action)
        self._robot_id = "".join(servo_ids(self.arm.name))
        self._home_q = np.radians(HOME_POSE_DEG)
        self._pack_q = np.radians(PACK_POSE_DEG)
        self._freezes = 0  # freezes and resets so far: one more while a command is planned cancels it
        self._power_on()

    # --- its parts, read-only: what a test inspects or wraps (a planner held mid-plan) --------------------

    @property
    def planner(self) -> Planner:
        return self._planner

    @property
    def motions(self) -> MotionQueue:
        return self._motions

    @property
    def environment(self) -> Environment:
        """The cell as the checks see it: obstacles, tool shape, contacts."""
        return self._environment

    @property
    def frames(self) -> Frames:
        """The base and tool frames."""
        return self._frames

    # --- state ---------------------------------------------------------------------------------------------

    def _power_on(self) -> None:
        self._mode = Mode.ACTIVE
        self._freezes += 1  # a reset cancels what is being planned too
        self._motions.reset(self._home_q, POWER_ON_GRIPPER, self._clock.now())
        self._io = IOBoard()
        self._frames = Frames()
        self._environment = Environment(self.arm, DEFAULT_TOOL)
        self._gripper_enabled = True
        self._stop_bindings: dict[int, SignalLevel] = {}
        self._failures.clear()

    def _failed(self) -> None:
        self._mode = Mode.MOTION_FAILED
        self._failures.record(
            FailureType.SOFTWARE_ERROR,
            FailureLevel.ERROR,
            "Motion failed: no clear way, the queue was dropped",
        )

    def _run_action(self, action: RobotAction) -> None:
        if isinstance(action, OutputAction):  # the gripper's actions live in the Motion's opening
            self._io.set_output(int(action.port), action.value)

    def _now(self) -> float:
        return self._clock.now()

    def check_alive(self) -> None:
        """Raise what every call answers in EMERGENCY (503) or when not responding (500)."""
        check_alive(self._mode)

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
            return motion_status(self._mode, self._motions.running(self._now()))

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
            self._motions.settle(self._now())  # waypoint actions due by now have set their outputs
            return self._io.output(port)

    def get_input(self, port: int) -> SignalLevel:
        with self._lock:
            self.check_alive()
            return self._io.input(port)

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
        """Stop where the arm is, drop the queue and hold the position (IDLE). In ERROR, a protective stop or
        twisted it stays so: only PUT /recover (PUT /untwisting/finish) leaves those, never a freeze."""
        with self._lock:
            self.check_alive()
            if self._mode in (Mode.ERROR, Mode.STOPPED, Mode.TWISTED):
                return
            self._freezes += 1  # cancels what is being planned (see the module doc)
            self._motions.stop(self._now())
            self._mode = Mode.ACTIVE

    def recover(self) -> RecoverResult:
        """ERROR, MOTION_FAILED or a protective stop -> IDLE (SUCCESS); IDLE stays IDLE (SUCCESS);
        RUNNING, ZERO_GRAVITY and TWISTED (PUT /untwisting/finish): nothing to recover from (FAILED)."""
        with self._lock:
            self.check_alive()
            if self._mode in (Mode.ERROR, Mode.MOTION_FAILED, Mode.STOPPED):
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
            configurations = self._configurations()
            for q in configurations:
                if not self._tool_clears_floor(q, T_flange_tool, tool.radius):
                    raise Collision()
            shape = self._environment.tool_shape
            geometry = self._environment.check_tool(shape, tool, configurations)
            self._frames.apply_tool(tool)
            self._environment.set_tool(shape, tool, geometry)
            return self._frames.tool

    def _configurations(self) -> list[np.ndarray]:
        """Where the arm is now and where its queued commands leave it (what a cell change must clear)."""
        now = self._now()
        return [self._motions.q_now(now), self._motions.end(now)[1]]

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

    def reset(self, *, keep_cell: bool = False) -> None:
        """Back to the power-on state: home pose, IDLE, IO low, default tool and base, cool servos, no
        obstacle. `keep_cell`: only the fault goes (as when a real arm's emergency stop is released and it
        is recovered): the arm stays where it stopped, with its obstacles, tool shape, tool, base and IO."""
        with self._lock:
            if not keep_cell:
                self._power_on()
                return
            self._motions.stop(self._now())
            self._freezes += 1  # what was being planned is dropped, as by a fault
            self._mode = Mode.ACTIVE
            self._failures.clear()

    def gripper_opening(self) -> float:
        """0 closed .. 1 open, at this instant (for the UI; answers in every state)."""
        with self._lock:
            return self._motions.gripper_now(self._now())

    def joint_positions(self) -> np.ndarray:
        """Joint angles in radians at this instant (for the UI; answers in every state)."""
        with self._lock:
            return np.array(self._motions.q_now(self._now()))
