"""The motion queue: queued commands as a timeline on the clock, where the arm rests, and the servos' heat.

The arm's state at any instant is a pure function of the queued Motions and the clock (see timeline.py):
`settle(now)` retires what is done by `now`. Callers hold the simulator's lock.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from pendant.controller.errors import PreconditionFailed
from pendant.controller.system_types import RobotAction
from pendant.controller.types import MotorStatus, Pose
from pendant.sim.motors import ServoModel
from pendant.sim.planner import Plan
from pendant.sim.timeline import Motion

MAX_QUEUED_COMMANDS = 100
# Finished motions kept for the thermal model before they are folded in (bounds memory if nobody reads).
_HISTORY_LIMIT = 256


def pose_of(q: np.ndarray) -> Pose:
    return Pose(angles=np.degrees(q).tolist())


class MotionQueue:
    """Queued motions, the configuration and gripper opening at rest, and the servo thermal model."""

    def __init__(
        self,
        servos: ServoModel,
        on_failed: Callable[[], None],
        on_action: Callable[[RobotAction], None],
    ) -> None:
        self.servos = servos
        self._on_failed = on_failed  # a queued command that cannot run was reached: MOTION_FAILED
        self._on_action = on_action  # a waypoint action is due (outputs; the gripper is in the Motion)
        self._fired = 0  # actions of the head motion already run
        self.queue: deque[Motion] = deque()
        self.history: list[Motion] = []
        self.rest_q = np.zeros(6)
        self.rest_gripper = 0.0
        self._thermal_q = np.zeros(6)
        self._pose_cache: Pose | None = None

    def reset(self, q: np.ndarray, gripper: float, now: float) -> None:
        self.queue.clear()
        self._fired = 0
        self.history = []
        self.rest_q = q.copy()
        self.rest_gripper = gripper
        self._pose_cache = None
        self.servos.reset(now)
        self._thermal_q = q.copy()

    def settle(self, now: float) -> Motion | None:
        """Retire the motions finished by `now`; the motion running at `now`, or None at rest."""
        queue = self.queue
        while queue:
            head = queue[0]
            if head.fails and head.t0 <= now:
                # Its turn came and it cannot run: the arm stays, the rest of the queue is dropped.
                queue.clear()
                self._pose_cache = None
                self._on_failed()
                break
            self._run_actions(head, now)
            if head.t_end > now:
                break
            done = queue.popleft()
            self._retire(done)
        if len(self.history) > _HISTORY_LIMIT:
            self.integrate_thermal(now)
        return queue[0] if queue else None

    def _run_actions(self, motion: Motion, until: float) -> None:
        actions = motion.actions
        while self._fired < len(actions) and motion.t0 + actions[self._fired][0] <= until:
            self._on_action(actions[self._fired][1])
            self._fired += 1

    def _retire(self, done: Motion) -> None:
        self._fired = 0
        self.rest_q = done.q_end
        self.rest_gripper = done.gripper_end
        self.history.append(done)
        self._pose_cache = None

    def q_now(self, now: float) -> np.ndarray:
        motion = self.settle(now)
        return self.rest_q if motion is None else motion.q_at(now)

    def pose_now(self, now: float) -> Pose:
        motion = self.settle(now)
        if motion is not None:
            return pose_of(motion.q_at(now))
        if self._pose_cache is None:
            self._pose_cache = pose_of(self.rest_q)
        return self._pose_cache

    def gripper_now(self, now: float) -> float:
        motion = self.settle(now)
        return self.rest_gripper if motion is None else motion.gripper_at(now)

    def running(self, now: float) -> bool:
        return self.settle(now) is not None

    def jogging(self, now: float) -> bool:
        motion = self.settle(now)
        return motion is not None and motion.jog

    def stop(self, now: float) -> None:
        """Stop dead where the arm is (freeze, relax, a fault) and forget the queued commands."""
        motion = self.settle(now)
        if motion is not None:
            self._retire(motion.cut(now))
        self.queue.clear()
        self._pose_cache = None

    def end(self, now: float) -> tuple[float, np.ndarray, float]:
        """(time, joint angles, gripper opening) at which the next queued command will start."""
        self.settle(now)
        if self.queue:
            last = self.queue[-1]
            return last.t_end, last.q_end, last.gripper_end
        return now, self.rest_q, self.rest_gripper

    def check_room(self, now: float, adding: int = 1) -> None:
        self.settle(now)  # what is done is no longer queued
        queued = len(self.queue)
        if queued + adding > MAX_QUEUED_COMMANDS:
            raise PreconditionFailed(
                f"queue must hold at most {MAX_QUEUED_COMMANDS} commands (got {queued} queued): "
                "wait for the arm to work through them"
            )

    def append(self, motion: Motion, now: float) -> None:
        self.queue.append(motion)
        self._pose_cache = None
        self.settle(now)

    def append_plan(
        self,
        plan: Plan | None,
        now: float,
        actions: tuple[tuple[float, RobotAction], ...] = (),
        jog: bool = False,
    ) -> None:
        """Queue a planned motion; None queues a command that fails when its turn comes (MOTION_FAILED)."""
        t0, q0, g0 = self.end(now)
        if plan is None:
            motion = Motion(t0=t0, duration=0.0, q_end=q0, gripper_start=g0, gripper_end=g0, fails=True)
        else:
            motion = Motion(
                t0=t0,
                duration=plan.duration,
                q_end=plan.q_end,
                gripper_start=g0,
                gripper_end=g0,
                plan=plan,
                actions=actions,
                jog=jog,
            )
            if actions:
                motion = replace(motion, gripper_end=motion.gripper_at(motion.t_end))
        self.append(motion, now)

    def append_gripper(self, target: float, duration_s: float, now: float) -> None:
        t0, q0, g0 = self.end(now)
        self.append(Motion(t0=t0, duration=duration_s, q_end=q0, gripper_start=g0, gripper_end=target), now)

    def place(self, q: np.ndarray, now: float) -> None:
        """The arm is put in `q` from outside (by hand): it rests there from now on."""
        self.integrate_thermal(now)
        self.rest_q = q
        self._thermal_q = q.copy()
        self._pose_cache = None

    def motors(self, now: float) -> list[MotorStatus]:
        motion = self.settle(now)
        self.integrate_thermal(now)
        if motion is None:
            zero = np.zeros(6)
            return self.servos.status(self.rest_q, zero, zero)
        return self.servos.status(*motion.state_at(now))

    def integrate_thermal(self, now: float) -> None:
        """Fold the motion history up to `now` into the servo temperatures."""
        servos = self.servos
        q_hold = self._thermal_q
        for motion in [*self.history, *self.queue]:
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
        self.history.clear()

    def _hold(self, q: np.ndarray, dt: float) -> None:
        zero = np.zeros(6)
        servos = self.servos
        servos.heat(servos.motor_current(servos.joint_torques(q, zero, zero)), dt)
