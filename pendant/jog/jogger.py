"""Hold-to-run jogging: motion only while the operator confirms, a freeze as soon as they stop, and a stop
that wins until the operator lets go (latch.py)."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

import numpy as np

from pendant.controller import Controller, ControllerError, MotionParams, MotionStatus, MotionType, Pose
from pendant.controller.stops import StopBus
from pendant.jog.arm import JogArm
from pendant.jog.blocked import Touching, why_blocked
from pendant.jog.deadman import DEADMAN_TIMEOUT_S, STALL_GRACE_S, Deadman, StallGrace
from pendant.jog.latch import Latch, SentJog
from pendant.jog.targets import (
    JOG_TCP_MAX_VELOCITY_M_S,
    JogFrame,
    JogRequest,
    cartesian_jog_path,
    joint_jog_target,
)
from pendant.kinematics.limits import JOINT_MAX_SPEED_RAD_S
from pendant.kinematics.transforms import matrix_to_position, position_to_matrix

log = logging.getLogger(__name__)

WATCHDOG_PERIOD_S = 0.01
# A target closer than this to where the arm is means "no progress possible" (limit, collision, edge).
MIN_PROGRESS_RAD = 1e-4
MSG_DEADMAN = "deadman: no confirmation from the page for {ms:.0f} ms"

# Told when a held jog ends other than by its release: the jog ("J1+") and the cause in the page's words.
OnStop = Callable[[str, str], None]


class Jogger:
    """Turns jog requests into controller motions guarded by a deadman.

    `hold(request)` is called on press and then repeatedly while the button is held (viser's on_hold);
    each call confirms the deadman. The watchdog freezes the arm `timeout_s` after the last confirmation.

    Any stop ends the held press for good (`latched`): a Freeze or protective stop heard on `stops`, the
    deadman, an obstacle or limit in the way, or the arm found stopped short of where the jog sent it (a
    controller's own stop). The press's confirmations are then refused until `release()`; a press from
    another holder (browser) starts afresh.

    A slow controller must never delay a stop: `release` takes no lock that a controller call holds, and a
    confirmation that arrives while an earlier one is still talking to the controller only confirms.
    """

    def __init__(
        self,
        controller: Controller,
        arm: JogArm,
        clock: Callable[[], float] = time.monotonic,
        timeout_s: float = DEADMAN_TIMEOUT_S,
        on_stop: OnStop | None = None,
        stops: StopBus | None = None,
        touching: Touching = lambda q: [],
    ) -> None:
        self._controller = controller
        self._arm = arm
        self._clock = clock
        self._touching = touching
        self.deadman = Deadman(clock, timeout_s)
        self._active: JogRequest | None = None
        self._sent: SentJog | None = None
        self._latch: Latch | None = None
        self._holder: object = None  # who sent the last confirmation
        self._confirmed_at = -float("inf")
        self._released = 0  # counts stops and releases: a motion sent across one must be frozen again
        self._lock = threading.RLock()  # one controller conversation at a time (holds and steps)
        self._state = threading.Lock()  # the fields above only: never held during a controller call
        self._on_stop = on_stop
        self._watchdog: threading.Thread | None = None
        self._stop_watchdog = threading.Event()
        if stops is not None:
            stops.subscribe(self.stop_heard)

    @property
    def active(self) -> JogRequest | None:
        return self._active

    @property
    def pressed(self) -> bool:
        """A jog is moving, or a stopped press is still latched."""
        return self._active is not None or self._latch is not None

    def latch_cause(self, holder: object = None) -> str | None:
        """Why `holder`'s press was stopped (its confirmations are refused until its release), or None."""
        latch = self._latch
        return latch.cause if latch is not None and latch.holder == holder else None

    @property
    def releases(self) -> int:
        """How many times a jog was stopped or released: read it where the page's messages arrive in order,
        and pass it to `hold`, so a confirmation sent before a stop but handled after it cannot restart."""
        with self._state:
            return self._released

    def hold(self, request: JogRequest, releases: int | None = None, holder: object = None) -> bool:
        """Confirm the deadman and keep `request` moving; False when the arm cannot go further that way, when
        this press was stopped (see `latch_cause`), or when the confirmation is stale (`releases`: the count
        it was sent under, and a stop or release came since)."""
        now = self._clock()
        with self._state:
            if releases is not None and releases != self._released:
                return False
            if self._latch is not None:
                if self._latch.holder == holder:
                    return False  # the button is still down after a stop: it stays stopped
                self._latch = None  # another browser's press
            self._holder, self._confirmed_at = holder, now
            seen = self._released  # a stop from here on refuses this confirmation
        self.deadman.confirm()
        if not self._lock.acquire(blocking=False):
            return True  # an earlier confirmation is still sending: this one has confirmed, that is enough
        try:
            return self._keep_moving(request, seen, now)
        finally:
            self._lock.release()

    def still_held(self, releases: int, holder: object = None) -> None:
        """The holder's confirmation as it arrives, before `hold` asks the controller on a worker thread: the
        running jog's deadman is confirmed at once, so a late worker (many browsers, a busy interpreter)
        does not count against the operator. Never starts nor restarts anything: only the jog `holder` is
        running, with no stop or release since `releases`, is kept alive."""
        with self._state:
            if self._active is None or self._latch is not None or holder != self._holder:
                return
            if releases != self._released:
                return
            self._confirmed_at = self._clock()
            self.deadman.confirm()

    def _keep_moving(self, request: JogRequest, releases: int, now: float) -> bool:
        status = self._controller.get_motion_status()
        running = status is MotionStatus.RUNNING
        sent = self._sent if self._active == request else None
        if sent is not None:
            if running:
                sent.seen_running = True
                return True
            if sent.starting(status, now):
                return True
            cause = sent.stopped_short(self._controller, status)
            if cause is not None:  # stopped by something the pendant did not hear of
                self._stop_press(cause, freeze=False, only_if=releases)
                return False
        elif running:  # another jog or motion is under way: stop it rather than queue behind it
            self._controller.freeze()
        with self._state:
            if releases != self._released:
                return False  # stopped meanwhile (while the previous motion was being frozen, say)
            self._active = request
        try:
            outcome = self._send(request)
        except ControllerError as error:  # refused (a protective stop, a fault): this press is over
            self._stop_press(error.message, freeze=False, only_if=releases)
            raise
        with self._state:
            stopped_meanwhile = self._released != releases
            if isinstance(outcome, SentJog) and not stopped_meanwhile:
                outcome.sent_at = now
                self._sent = outcome
        if stopped_meanwhile:  # the stop went out before this motion reached the controller
            self._controller.freeze()
            return False
        if isinstance(outcome, str):
            self._stop_press(outcome, freeze=False, only_if=releases)
            return False
        return True

    def step(self, request: JogRequest) -> bool:
        """One increment (`request.step`), no hold needed: the arm stops at its end."""
        with self._lock:
            return isinstance(self._send(request), SentJog)

    def release(self, reason: str = "released") -> None:
        """The operator let go (button released, page closed, control handed over): stop the jog now, and
        the next press starts afresh."""
        with self._state:
            self._latch = None
            self._released += 1  # a confirmation sent before the release cannot restart the arm
            self._confirmed_at = -float("inf")
            active, self._active, self._sent = self._active, None, None
            self.deadman.disarm()
        if active is None:
            return
        try:
            self._controller.freeze()
        finally:
            self._tell(active, reason)

    def stop_heard(self, cause: str) -> None:
        """A stop from elsewhere (Freeze in any browser, the API, a protective stop): the held press ends
        for good. Called before the stop reaches the controller, on any thread: no controller call here."""
        self._stop_press(cause, freeze=False, held_only=True)

    def check_deadman(self) -> bool:
        """Freeze if the operator stopped confirming; True when it fired."""
        if self._active is not None and self.deadman.expired():
            log.info("deadman: no confirmation for %.0f ms, freezing", self.deadman.timeout_s * 1000)
            self._stop_press(MSG_DEADMAN.format(ms=self.deadman.timeout_s * 1000), freeze=True)
            return True
        return False

    def _stop_press(
        self, cause: str, *, freeze: bool, held_only: bool = False, only_if: int | None = None
    ) -> None:
        """Latch the held press with `cause` (freezing the arm when `freeze`). `held_only`: only if a press
        is held now; `only_if`: only if no stop or release came since that count."""
        with self._state:
            if only_if is not None and only_if != self._released:
                return
            held = self._active is not None or self._clock() - self._confirmed_at <= self.deadman.timeout_s
            if held_only and not held:
                return
            self._latch = Latch(self._holder, cause)
            self._released += 1
            active, self._active, self._sent = self._active, None, None
            self.deadman.disarm()
        try:
            if freeze and active is not None:
                self._controller.freeze()
        finally:
            self._tell(active, cause)

    def _tell(self, request: JogRequest | None, cause: str) -> None:
        if self._on_stop is not None and request is not None:
            self._on_stop(request.label(), cause)

    def start_watchdog(self) -> None:
        def run() -> None:
            wakes = StallGrace(WATCHDOG_PERIOD_S, time.monotonic())  # the real clock: its waits are real
            while not self._stop_watchdog.wait(WATCHDOG_PERIOD_S):
                if wakes.woke_late(time.monotonic()):
                    if self._stop_watchdog.wait(STALL_GRACE_S):
                        return
                    wakes.restart(time.monotonic())
                try:
                    self.check_deadman()
                except ControllerError as error:
                    log.warning("deadman freeze refused: %s", error.message)
                except Exception:  # whatever a listener does, the watchdog must go on watching
                    log.exception("deadman check failed")

        self._watchdog = threading.Thread(target=run, name="jog-deadman", daemon=True)
        self._watchdog.start()

    def stop_watchdog(self) -> None:
        self._stop_watchdog.set()
        if self._watchdog is not None:
            self._watchdog.join(timeout=1.0)

    def _send(self, request: JogRequest) -> SentJog | str:
        """Send the motion; what was sent, or why the arm cannot go that way (nothing sent)."""
        q = np.radians(np.asarray(self._controller.get_pose().angles, dtype=float))
        speed = float(np.clip(request.speed_percent, 1.0, 100.0))
        tcp_cap = max(0.001, JOG_TCP_MAX_VELOCITY_M_S * speed / 100.0)
        if request.frame is JogFrame.JOINT:
            joint_speed = float(JOINT_MAX_SPEED_RAD_S[request.axis]) * speed / 100.0
            target = joint_jog_target(self._arm, q, request, joint_speed)
            if abs(target[request.axis] - q[request.axis]) < MIN_PROGRESS_RAD:
                return why_blocked(self._arm, q, request, self._touching)
            params = MotionParams(speed=speed, tcp_max_velocity=JOG_TCP_MAX_VELOCITY_M_S)
            self._controller.set_pose(Pose(angles=[float(v) for v in np.degrees(target)]), params)
            return SentJog(request, target, self._clock())
        T_base_zero = position_to_matrix(self._controller.get_base())
        T_flange_tool = position_to_matrix(self._controller.get_tool().position)
        T_zero_tool = np.linalg.inv(T_base_zero) @ self._arm.fk(q) @ T_flange_tool
        target_T = cartesian_jog_path(self._arm, q, T_base_zero, T_flange_tool, request)
        if np.allclose(target_T, T_zero_tool, atol=1e-6):
            return why_blocked(self._arm, q, request, self._touching, T_base_zero, T_flange_tool)
        params = MotionParams(speed=speed, motion_type=MotionType.LINEAR, tcp_max_velocity=tcp_cap)
        self._controller.set_position(matrix_to_position(target_T), params)
        return SentJog(request, target_T, self._clock())
