"""Hold-to-run jogging: motion only while the operator confirms, a freeze as soon as they stop."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

import numpy as np

from pendant.controller import Controller, ControllerError, MotionParams, MotionStatus, MotionType, Pose
from pendant.jog.deadman import DEADMAN_TIMEOUT_S, Deadman
from pendant.jog.targets import (
    JOG_TCP_MAX_VELOCITY_M_S,
    JogFrame,
    JogRequest,
    cartesian_jog_path,
    joint_jog_target,
)
from pendant.kinematics import ArmModel
from pendant.kinematics.limits import JOINT_MAX_SPEED_RAD_S
from pendant.kinematics.transforms import matrix_to_position, position_to_matrix

log = logging.getLogger(__name__)

WATCHDOG_PERIOD_S = 0.01
# A target closer than this to where the arm is means "no progress possible" (limit, collision, edge).
MIN_PROGRESS_RAD = 1e-4


class Jogger:
    """Turns jog requests into controller motions guarded by a deadman.

    `hold(request)` is called on press and then repeatedly while the button is held (viser's on_hold);
    each call confirms the deadman. The watchdog freezes the arm `timeout_s` after the last confirmation.

    A slow controller must never delay a stop: `release` takes no lock that a controller call holds, and a
    confirmation that arrives while an earlier one is still talking to the controller only confirms.
    """

    def __init__(
        self,
        controller: Controller,
        arm: ArmModel,
        clock: Callable[[], float] = time.monotonic,
        timeout_s: float = DEADMAN_TIMEOUT_S,
        on_stop: Callable[[str], None] | None = None,
    ) -> None:
        self._controller = controller
        self._arm = arm
        self.deadman = Deadman(clock, timeout_s)
        self._active: JogRequest | None = None
        self._released = 0  # counts releases: a motion sent across one must be frozen again
        self._lock = threading.RLock()  # one controller conversation at a time (holds and steps)
        self._state = threading.Lock()  # `_active` and `_released` only: never held during a controller call
        self._on_stop = on_stop
        self._watchdog: threading.Thread | None = None
        self._stop_watchdog = threading.Event()

    @property
    def active(self) -> JogRequest | None:
        return self._active

    @property
    def releases(self) -> int:
        """How many times a jog was stopped: read it where the page's messages arrive in order, and pass it
        to `hold`, so a confirmation sent before a release but handled after it cannot restart the arm."""
        with self._state:
            return self._released

    def hold(self, request: JogRequest, releases: int | None = None) -> bool:
        """Confirm the deadman and keep `request` moving; False when the arm cannot go further that way, or
        when the confirmation is stale (`releases`: the count it was sent under, and a release came since)."""
        with self._state:
            if releases is not None and releases != self._released:
                return False
        self.deadman.confirm()
        if not self._lock.acquire(blocking=False):
            return True  # an earlier confirmation is still sending: this one has confirmed, that is enough
        try:
            running = self._controller.get_motion_status() is MotionStatus.RUNNING
            if self._active == request and running:
                return True
            if running:  # another jog or motion is under way: stop it rather than queue behind it
                self._controller.freeze()
            with self._state:
                if releases is not None and releases != self._released:
                    return False  # released while the previous motion was being frozen
                self._active = request
                releases = self._released
            moved = self._send(request)
            with self._state:
                released_meanwhile = self._released != releases
                if not moved and not released_meanwhile:
                    self._active = None
                    self.deadman.disarm()
            if released_meanwhile:  # the stop went out before this motion reached the controller
                self._controller.freeze()
                return False
            return moved
        finally:
            self._lock.release()

    def step(self, request: JogRequest) -> bool:
        """One increment (`request.step`), no hold needed: the arm stops at its end."""
        with self._lock:
            return self._send(request)

    def release(self, reason: str = "released") -> None:
        """Stop the jog now (button released, operator left, or the deadman fired)."""
        with self._state:
            if self._active is None:
                return
            self._active = None
            self._released += 1
            self.deadman.disarm()
        try:
            self._controller.freeze()
        finally:
            if self._on_stop is not None:
                self._on_stop(reason)

    def check_deadman(self) -> bool:
        """Freeze if the operator stopped confirming; True when it fired."""
        if self._active is not None and self.deadman.expired():
            log.info("deadman: no confirmation for %.0f ms, freezing", self.deadman.timeout_s * 1000)
            self.release("deadman")
            return True
        return False

    def start_watchdog(self) -> None:
        def run() -> None:
            while not self._stop_watchdog.wait(WATCHDOG_PERIOD_S):
                try:
                    self.check_deadman()
                except ControllerError as error:
                    log.warning("deadman freeze refused: %s", error.message)

        self._watchdog = threading.Thread(target=run, name="jog-deadman", daemon=True)
        self._watchdog.start()

    def stop_watchdog(self) -> None:
        self._stop_watchdog.set()
        if self._watchdog is not None:
            self._watchdog.join(timeout=1.0)

    def _send(self, request: JogRequest) -> bool:
        q = np.radians(np.asarray(self._controller.get_pose().angles, dtype=float))
        speed = float(np.clip(request.speed_percent, 1.0, 100.0))
        tcp_cap = max(0.001, JOG_TCP_MAX_VELOCITY_M_S * speed / 100.0)
        if request.frame is JogFrame.JOINT:
            joint_speed = float(JOINT_MAX_SPEED_RAD_S[request.axis]) * speed / 100.0
            target = joint_jog_target(self._arm, q, request, joint_speed)
            if abs(target[request.axis] - q[request.axis]) < MIN_PROGRESS_RAD:
                return False
            params = MotionParams(speed=speed, tcp_max_velocity=JOG_TCP_MAX_VELOCITY_M_S)
            self._controller.set_pose(Pose(angles=[float(v) for v in np.degrees(target)]), params)
            return True
        T_base_zero = position_to_matrix(self._controller.get_base())
        T_flange_tool = position_to_matrix(self._controller.get_tool().position)
        T_zero_tool = np.linalg.inv(T_base_zero) @ self._arm.fk(q) @ T_flange_tool
        target_T = cartesian_jog_path(self._arm, q, T_base_zero, T_flange_tool, request)
        if np.allclose(target_T, T_zero_tool, atol=1e-6):
            return False
        params = MotionParams(speed=speed, motion_type=MotionType.LINEAR, tcp_max_velocity=tcp_cap)
        self._controller.set_position(matrix_to_position(target_T), params)
        return True
