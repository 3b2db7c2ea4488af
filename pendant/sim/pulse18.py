"""The operations Rozum's SDK 1.8.4 adds to the reference guide's, on the simulator (a SimController mixin).

System state and failures, identity and versions, the tool's two views and shape, the environment, jogging,
free drive, the protective stop and its input bindings, gripper power, untwisting, the motors' log, and the
/run/* motions. They share SimController's lock, state and queue (see controller.py).
"""

from __future__ import annotations

import threading

import numpy as np

from pendant.controller.cell_types import Obstacle, ToolInfo, ToolShape
from pendant.controller.errors import (
    MSG_JOG_BLOCKED,
    MSG_PROTECTIVE_STOP,
    Collision,
    ControllerError,
    NotResponding,
    PreconditionFailed,
    Unreachable,
)
from pendant.controller.system_types import (
    Failure,
    FailureLevel,
    FailureType,
    JoggingVector,
    JointMotionParameters,
    LinearMotionParameters,
    PoseWaypoint,
    PositionWaypoint,
    RobotInfo,
    SystemState,
    Version,
)
from pendant.controller.types import INPUT_PORTS, MotionParams, MotionType, SignalLevel, Tool
from pendant.kinematics.contact import ContactGuard
from pendant.kinematics.transforms import inverse, rotvec_to_matrix
from pendant.sim import identity
from pendant.sim.host import SimHost
from pendant.sim.io import check_port
from pendant.sim.moves import Start, Step
from pendant.sim.states import Mode, check_alive, check_can_move, system_state

MSG_JOG_WHILE_MOVING = "The arm is moving: jogging starts from rest (PUT /freeze first)"
# Jogging: full strength (1.0) moves the TCP at 250 mm/s (ISO 10218-1 reduced speed) and turns it at
# 0.5 rad/s; a jog is planned this far ahead and ends early at a limit, the workspace edge or an obstacle.
JOG_MAX_SPEED_M_S = 0.25
JOG_MAX_TURN_RAD_S = 0.5
JOG_TCP_ACCELERATION_M_S2 = 0.5
JOG_HORIZON_S = 10.0
JOG_SCAN_STEPS = 80
JOG_PLAN_TRIES = 4
MOTORS = 6


class Pulse18Operations:
    """SDK 1.8.4's operations; every method answers like the reference's (503 in EMERGENCY, and so on),
    except GET /status and GET /status/failure, which answer in EMERGENCY too (the SDK's README asks them
    why a script failed)."""

    _lock: threading.RLock

    # --- state and identity --------------------------------------------------------------------------------

    def clock_time(self: SimHost) -> float:
        """The Unix time of the simulator clock's present: readings are stamped in the simulator's own time
        (a fake or scaled clock included)."""
        now = self._clock.now()
        return self._epoch + now if self._epoch is not None else self._clock.unix_time(now)

    def get_system_state(self: SimHost) -> SystemState:
        with self._lock:
            if self._mode is Mode.NO_RESPONSE:
                raise NotResponding()
            now = self._now()
            return system_state(self._mode, self._motions.running(now), self._motions.jogging(now))

    def get_failures(self: SimHost) -> list[Failure]:
        with self._lock:
            if self._mode is Mode.NO_RESPONSE:
                raise NotResponding()
            return self._failures.recent()

    def get_robot_info(self: SimHost) -> RobotInfo:
        with self._lock:
            check_alive(self._mode)
            return identity.robot_info(self.model)

    def get_hardware_version(self: SimHost) -> Version:
        with self._lock:
            check_alive(self._mode)
            return identity.hardware_version(self.model)

    def get_software_version(self: SimHost) -> Version:
        with self._lock:
            check_alive(self._mode)
            return identity.software_version(self.model)

    def get_robot_software_version(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            return identity.ROBOT_SOFTWARE_VERSION

    def read_motors_log(self: SimHost) -> int:
        """Reads the motors' logs: the number read (one per motor)."""
        with self._lock:
            check_alive(self._mode)
            return MOTORS

    # --- the tool's two views and its shape ----------------------------------------------------------------

    def get_tool_info(self: SimHost) -> ToolInfo:
        with self._lock:
            check_alive(self._mode)
            tool = self._frames.tool
            return ToolInfo(name=tool.name, tcp=tool.position)

    def set_tool_info(self: SimHost, info: ToolInfo) -> ToolInfo:
        """The same tool as POST /tool, keeping its radius: name and TCP."""
        with self._lock:
            radius = self._frames.tool.radius
            tool = Tool(name=info.name, point=info.tcp.point, rotation=info.tcp.rotation, radius=radius)
            self.set_tool(tool)
            return ToolInfo(name=tool.name, tcp=tool.position)

    def get_tool_shape(self: SimHost) -> ToolShape:
        with self._lock:
            check_alive(self._mode)
            return self._environment.tool_shape

    def set_tool_shape(self: SimHost, shape: ToolShape) -> ToolShape:
        """Capsules on the flange, checked against obstacles and the floor in every motion from now on;
        refused (412) when they would touch one where the arm is or where its queue ends."""
        with self._lock:
            check_alive(self._mode)
            tool = self._frames.tool
            geometry = self._environment.check_tool(shape, tool, self._configurations())
            self._environment.set_tool(shape, tool, geometry)
            return shape

    # --- environment ---------------------------------------------------------------------------------------

    def add_obstacle(self: SimHost, obstacle: Obstacle) -> str:
        with self._lock:
            check_alive(self._mode)
            links = self._environment.add(obstacle, *self._configurations())
            touching = f" touching the arm ({', '.join(links)})" if links else ""
            return f"Obstacle {obstacle.name!r} added{touching}"

    def get_obstacles(self: SimHost) -> list[Obstacle]:
        with self._lock:
            check_alive(self._mode)
            return list(self._environment.obstacles.values())

    def get_obstacle(self: SimHost, name: str) -> Obstacle:
        with self._lock:
            check_alive(self._mode)
            return self._environment.get(name)

    def remove_obstacles(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            self._environment.clear()
            return "All obstacles removed"

    def remove_obstacle(self: SimHost, name: str) -> str:
        with self._lock:
            check_alive(self._mode)
            self._environment.remove(name)
            return f"Obstacle {name!r} removed"

    # --- gripper power, free drive, protective stop, untwisting --------------------------------------------

    def enable_gripper(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            self._gripper_enabled = True
            return "Gripper enabled"

    def disable_gripper(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            self._gripper_enabled = False
            return "Gripper disabled: it may be unplugged"

    def zg_on(self: SimHost) -> str:
        self.relax()
        return "Zero gravity on: the arm can be moved by hand"

    def zg_off(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            if self._mode is Mode.ZERO_GRAVITY:
                self._mode = Mode.ACTIVE
            return "Zero gravity off"

    def stop(self: SimHost) -> str:
        """Protective stop: the arm stops where it is, holds, and refuses motion until PUT /recover."""
        with self._lock:
            check_alive(self._mode)
            if self._mode is not Mode.ERROR:
                self._protective_stop("Protective stop (POST /stop)")
            return MSG_PROTECTIVE_STOP

    def _protective_stop(self: SimHost, reason: str) -> None:
        self._freezes += 1  # cancels what is being planned, as a freeze does
        self._motions.stop(self._now())
        self._mode = Mode.STOPPED
        self._failures.record(FailureType.STOP_2, FailureLevel.WARN, reason)

    def bind_stop(self: SimHost, port: int, level: SignalLevel) -> str:
        with self._lock:
            check_alive(self._mode)
            self._stop_bindings[check_port(port, INPUT_PORTS, "input")] = SignalLevel(level)
            return f"Stop bound to digital input {port} going {SignalLevel(level).value}"

    def unbind_stop(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            self._stop_bindings.clear()
            return "Stop unbound from the inputs"

    def finish_untwisting(self: SimHost) -> str:
        with self._lock:
            check_alive(self._mode)
            if self._mode is not Mode.TWISTED:
                return "The arm is not twisted: nothing to finish"
            self._motions.stop(self._now())
            self._mode = Mode.ACTIVE
            return "Untwisting finished: the arm is ready"

    # --- /run/* --------------------------------------------------------------------------------------------

    def run_linear_positions(
        self: SimHost, positions: list[PositionWaypoint], params: LinearMotionParameters
    ) -> str:
        self.run_positions(list(positions), _linear(params))
        return "Motion accepted"

    def run_linear_poses(self: SimHost, poses: list[PoseWaypoint], params: LinearMotionParameters) -> str:
        self.run_poses(list(poses), _linear(params))
        return "Motion accepted"

    def run_joint_positions(
        self: SimHost, positions: list[PositionWaypoint], params: JointMotionParameters
    ) -> str:
        self.run_positions(list(positions), _joint(params))
        return "Motion accepted"

    def run_joint_poses(self: SimHost, poses: list[PoseWaypoint], params: JointMotionParameters) -> str:
        self.run_poses(list(poses), _joint(params))
        return "Motion accepted"

    # --- jogging -------------------------------------------------------------------------------------------

    def jog(self: SimHost, vector: JoggingVector) -> str:
        """Move the TCP along (and turn it about) base-frame axes until an all-zero vector, a freeze, a stop,
        a limit or an obstacle; a new vector while jogging changes the direction."""
        linear = np.array([vector.x, vector.y, vector.z]) * JOG_MAX_SPEED_M_S
        turn = np.array([vector.rx, vector.ry, vector.rz]) * JOG_MAX_TURN_RAD_S
        with self._lock:
            check_can_move(self._mode)
            now = self._now()
            jogging = self._motions.jogging(now)
            if not linear.any() and not turn.any():
                if jogging:
                    self._motions.stop(now)
                return "Jogging stopped"
            if self._motions.running(now) and not jogging:
                raise PreconditionFailed(MSG_JOG_WHILE_MOVING)
            if jogging:
                self._motions.stop(now)
        strength = max(
            float(np.max(np.abs([vector.x, vector.y, vector.z, vector.rx, vector.ry, vector.rz]))), 0.01
        )
        params = MotionParams(
            speed=100.0 * strength,
            motion_type=MotionType.LINEAR,
            tcp_max_velocity=max(float(np.linalg.norm(linear)), 1e-3),
            tcp_acceleration=JOG_TCP_ACCELERATION_M_S2,
        )
        self._plan_and_enqueue(lambda start: self._plan_jog(start, linear, turn, params), jog=True)
        return "Jogging"

    def _plan_jog(
        self: SimHost, start: Start, linear: np.ndarray, turn: np.ndarray, params: MotionParams
    ) -> list[Step]:
        T0 = self.arm.fk(start.q) @ start.T_flange_tool
        T_tool_flange = inverse(start.T_flange_tool)

        def target(fraction: float) -> np.ndarray:
            T = np.eye(4)
            T[:3, 3] = T0[:3, 3] + linear * JOG_HORIZON_S * fraction
            T[:3, :3] = rotvec_to_matrix(turn * JOG_HORIZON_S * fraction) @ T0[:3, :3]
            return T

        # The farthest point of the horizon reached before IK fails or something is touched.
        reach, q_near = 0.0, start.q
        guard = ContactGuard(start.cell, start.q) if start.cell is not None else None
        for k in range(1, JOG_SCAN_STEPS + 1):
            fraction = k / JOG_SCAN_STEPS
            q = self.arm.ik(target(fraction) @ T_tool_flange, q_near)
            if q is None or (guard.check(q) is not None if guard is not None else self.arm.in_collision(q)):
                break
            reach, q_near = fraction, q
        last_error: ControllerError = Unreachable(MSG_JOG_BLOCKED)
        for _ in range(JOG_PLAN_TRIES):
            if reach <= 0.0:
                break
            try:
                plan = self._planner.linear(
                    start.q,
                    [target(reach)],
                    params,
                    start.T_flange_tool,
                    start.tool_radius,
                    MSG_JOG_BLOCKED,
                    cell=start.cell,
                )
                return [Step(plan)]
            except (Unreachable, Collision) as error:
                last_error, reach = error, reach * 0.5
        raise PreconditionFailed(MSG_JOG_BLOCKED) from last_error


def _linear(params: LinearMotionParameters) -> MotionParams:
    """Metres per second and m/s^2 at the TCP; the joints may use their full speed and acceleration."""
    return MotionParams(
        speed=100.0,
        motion_type=MotionType.LINEAR,
        tcp_max_velocity=params.velocity,
        acceleration=100.0,
        interpolation=params.interpolationType,
        tcp_acceleration=params.acceleration,
    )


def _joint(params: JointMotionParameters) -> MotionParams:
    """Percent of the joints' speed and acceleration limits."""
    return MotionParams(
        speed=params.velocity,
        motion_type=MotionType.JOINT,
        acceleration=params.acceleration,
        interpolation=params.interpolation_type,
    )
