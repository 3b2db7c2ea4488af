"""The command queue as a timeline: each queued command is a Motion with an absolute start time.

A Motion starts when the one before it ends (or when it was sent, if the arm was at rest), so the arm's state
at any instant is a pure function of the commands and the clock: nothing runs in the background.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.controller.system_types import GripperAction, RobotAction
from pendant.sim.io import GRIPPER_CLOSED, GRIPPER_OPEN
from pendant.sim.planner import Plan


@dataclass(frozen=True)
class Motion:
    """One queued command: a planned arm motion, or a gripper action (the arm holds still meanwhile)."""

    t0: float
    duration: float
    q_end: np.ndarray
    gripper_start: float
    gripper_end: float
    plan: Plan | None = None  # None: a gripper action, the arm holds q_end
    fails: bool = False  # a command that turned out impossible: when reached, the queue stops (MOTION_FAILED)
    # Waypoint actions (SDK >= 1.7), seconds after t0, in time order: outputs and gripper, run when reached.
    actions: tuple[tuple[float, RobotAction], ...] = ()
    jog: bool = False  # a jog (PUT /jogging): the state is JOGGING while it runs

    @property
    def t_end(self) -> float:
        return self.t0 + self.duration

    def q_at(self, t: float) -> np.ndarray:
        """Joint angles (radians) at clock time t."""
        u = t - self.t0
        if self.plan is None or u >= self.duration:
            return self.q_end
        if u <= 0.0:
            return self.plan.path.q(0.0)
        return self.plan.path.q(self.plan.scaling.at(u)[0])

    def state_at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, dq/dt, d2q/dt2) at clock time t."""
        zero = np.zeros_like(self.q_end)
        u = t - self.t0
        if self.plan is None or u >= self.duration:
            return self.q_end, zero, zero
        s, s_dot, s_ddot = self.plan.scaling.at(max(u, 0.0))
        q, dq_ds, d2q_ds2 = self.plan.path.derivatives(s)
        return q, dq_ds * s_dot, d2q_ds2 * (s_dot * s_dot) + dq_ds * s_ddot

    def gripper_at(self, t: float) -> float:
        """Gripper opening (0 closed .. 1 open) at clock time t."""
        if self.actions:  # a run that opens or closes the gripper at its waypoints
            opening = self.gripper_start
            for dt, action in self.actions:
                if self.t0 + dt > t:
                    break
                if isinstance(action, GripperAction):
                    opening = GRIPPER_OPEN if action.value == "OPEN" else GRIPPER_CLOSED
            return opening
        if self.duration <= 0.0 or t >= self.t_end:
            return self.gripper_end
        fraction = max(0.0, (t - self.t0) / self.duration)
        return self.gripper_start + (self.gripper_end - self.gripper_start) * fraction

    def cut(self, t: float) -> Motion:
        """This motion stopped dead at clock time t (freeze, relax, a fault): it ends where it was."""
        if t >= self.t_end:
            return self
        t = max(t, self.t0)
        return Motion(
            t0=self.t0,
            duration=t - self.t0,
            q_end=np.array(self.q_at(t)),
            gripper_start=self.gripper_start,
            gripper_end=self.gripper_at(t),
            plan=self.plan,
            actions=tuple(item for item in self.actions if self.t0 + item[0] <= t),
            jog=self.jog,
        )
