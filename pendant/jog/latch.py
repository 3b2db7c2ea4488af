"""A stop wins until the operator lets go: the press a stop ended, and the motion a press last sent.

A stopped press stays stopped while its confirmations keep coming (the button is still down): only its
release, or a press from another browser, ends the latch. Confirmations that stop and start again (a page
that hung, then ran) do not: the operator never let go.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.controller import Controller, MotionStatus
from pendant.jog.targets import JogFrame, JogRequest
from pendant.kinematics.transforms import position_to_matrix

# The arm counts as at the end of a jog's horizon (not stopped on the way) this close to where it was sent.
ARRIVED_RAD = np.radians(0.5)
ARRIVED_M = 0.001
# A controller behind a link may report IDLE for a moment after accepting a motion (proxy mode): a jog seen
# idle short of its target this soon after the send, never seen running, is taken as not started yet.
SEND_SETTLE_S = 0.5
MSG_STOPPED_OUTSIDE = "stopped outside the pendant (the controller, or a client it answers directly)"


@dataclass(frozen=True)
class Latch:
    """The press (`holder`: who pressed, e.g. a browser's id) a stop ended, and why."""

    holder: object
    cause: str


@dataclass
class SentJog:
    """A continuous jog's motion as sent: where it goes (joint angles, or T_zero_tool) and when it left."""

    request: JogRequest
    target: np.ndarray
    sent_at: float
    seen_running: bool = False

    def arrived(self, controller: Controller) -> bool:
        if self.request.frame is JogFrame.JOINT:
            q = np.radians(np.asarray(controller.get_pose().angles, dtype=float))
            return bool(np.max(np.abs(q - self.target)) <= ARRIVED_RAD)
        T = position_to_matrix(controller.get_position())
        turned = np.arccos(np.clip((np.trace(T[:3, :3].T @ self.target[:3, :3]) - 1.0) / 2.0, -1.0, 1.0))
        return bool(np.linalg.norm(T[:3, 3] - self.target[:3, 3]) <= ARRIVED_M and turned <= ARRIVED_RAD)

    def starting(self, status: MotionStatus, now: float) -> bool:
        """Idle, never seen running and just sent: the controller may not have started it yet."""
        return status is MotionStatus.IDLE and not self.seen_running and now - self.sent_at < SEND_SETTLE_S

    def stopped_short(self, controller: Controller, status: MotionStatus) -> str | None:
        """Why the arm, not running, stopped before this motion's end; None when it got there (the next
        piece follows)."""
        if status is not MotionStatus.IDLE:
            return f"the controller stopped it ({status.value})"
        return None if self.arrived(controller) else MSG_STOPPED_OUTSIDE
