"""Robot commands from the page: each runs off the UI thread, and a refusal shows the controller's message."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import viser

from pendant.controller import Controller, ControllerError, MotionParams, Pose
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.stop_path import on_stop_press

log = logging.getLogger(__name__)

HOME_POSE_DEG = (0.0, -90.0, 0.0, -90.0, -90.0, 0.0)
HOME_SPEED_PERCENT = 20.0
FREEZE_HOTKEY = "escape"
FREEZE_HOTKEY_LABEL = "Esc"


Gate = Callable[[viser.ClientHandle | None], str | None]
# Why the page may not move the arm now (a program is running), or None.
MotionBlock = Callable[[], str | None]
# Told of every stop (an urgent command) before it goes to the controller, with its cause in the page's
# words ("Freeze by browser #2").
OnStop = Callable[[str], None]
# Says who pressed a stop, for its cause (the page's browser names).
Presser = Callable[[viser.ClientHandle | None], str]
# Told of every command, for the event log: label, sender, refusal (None: accepted) and, for a controller
# call, its future (None: an action of the pendant's own, such as a program edit or run).
OnSubmit = Callable[[str, viser.ClientHandle | None, str | None, Future[object] | None], None]


class CommandRefused(Exception):
    """The page refused a command before it reached the controller (e.g. the browser is only a viewer)."""


def notify_refusal(client: viser.ClientHandle | None, title: str, message: str) -> None:
    log.warning("%s: %s", title, message)
    if client is not None:
        client.add_notification(title=title, body=message, color="red", auto_close_seconds=8.0)


class CommandRunner:
    """Sends commands to the controller on a worker thread so a slow controller never blocks the page.

    `gate(client)` says why a browser may not command (None: it may); internal callers pass client=None.
    Urgent commands (Freeze) skip the gate, since stopping is always allowed, and run on their own thread
    so they never wait behind a slow command. `motion_block()` says why a browser may not move the arm now
    (a program is running); commands sent with `motion=True` are then refused.
    """

    def __init__(self, controller: Controller, gate: Gate | None = None) -> None:
        self._controller = controller
        self.gate: Gate = gate if gate is not None else (lambda client: None)
        self.on_submit: OnSubmit | None = None
        self.on_stop: OnStop | None = None  # e.g. the held jog stays stopped until released
        self.presser: Presser = lambda client: "pendant" if client is None else f"browser #{client.client_id}"
        self.motion_block: MotionBlock = lambda: None
        self.stops_sent = 0  # how many stops were pressed: work begun before one (a plan) is dropped
        # Words a refusal of a motion needs besides the controller's own (the arm is in ERROR: Recover).
        self.explain: Callable[[str], str] = lambda message: message
        self._pool = ThreadPoolExecutor(max_workers=2, thread_name_prefix="pendant-command")
        self._urgent = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pendant-freeze")
        # A stop button's press, handed over from viser's event loop (stop_path.py): never viser's shared
        # callback pool, which any browser's clicks can fill.
        self._presses = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pendant-stop-press")
        # Set when the page closes (SIGTERM, Ctrl-C): long work on the workers (the page's pre-flight) ends
        # at its next look instead of keeping the process alive until it is done (Python joins the workers).
        self.quitting = threading.Event()

    @property
    def controller(self) -> Controller:
        return self._controller

    def refusal(self, client: viser.ClientHandle | None, label: str, *, motion: bool = False) -> str | None:
        """Why `client` may not send `label` (and tell it so), or None; `motion`: it moves the arm."""
        reason = self.gate(client) if client is not None else None
        if reason is None and motion and client is not None:
            reason = self.motion_block()
        if reason is not None:
            notify_refusal(client, f"{label} refused", reason)
            if self.on_submit is not None:
                self.on_submit(label, client, reason, None)
        return reason

    def record(self, label: str, client: viser.ClientHandle | None) -> None:
        """Tell the event log of an accepted action that is not a controller call (a program edit, Run)."""
        if self.on_submit is not None:
            self.on_submit(label, client, None, None)

    def submit(
        self,
        label: str,
        action: Callable[[Controller], object],
        client: viser.ClientHandle | None,
        *,
        urgent: bool = False,
        motion: bool = False,
        announce: bool = True,
        ending: Callable[[str], None] | None = None,
    ) -> Future[object]:
        """`urgent`: a stop (never gated, never behind another command), told to `on_stop` first unless
        `announce` is False (Pause holds a run without ending it). `ending`: told the stop's cause before
        anyone else, on the caller's thread: the program's Stop marks its run as ending for good, so that the
        run ends so whichever it hears first, the announcement or `action` on the urgent thread."""
        if urgent:
            self.stops_sent += 1
            cause = f"{label} by {self.presser(client)}"
            if ending is not None:
                try:
                    ending(cause)
                except Exception:  # the stop itself goes out whatever
                    log.exception("marking %r as ending the run failed", label)
            if announce and self.on_stop is not None:
                self.on_stop(cause)  # before the stop goes out: a jog confirmation then cannot undo it
        reason = None if urgent else self.refusal(client, label, motion=motion)
        if reason is not None:  # refusal() has told the page and the event log
            refused: Future[object] = Future()
            refused.set_exception(CommandRefused(reason))
            return refused

        def run() -> object:
            try:
                return action(self._controller)
            except ControllerError as error:
                notify_refusal(
                    client, f"{label} refused", self.explain(error.message) if motion else error.message
                )
                raise

        future = (self._urgent if urgent else self._pool).submit(run)
        if self.on_submit is not None:
            self.on_submit(label, client, None, future)
        return future

    def press(self, pressed: Callable[[], object]) -> Future[object] | None:
        """Run a stop button's press on the stop thread (see stop_path.py); a failure is logged."""
        try:
            future = self._presses.submit(pressed)
        except RuntimeError:  # shut down: the page is closing
            log.warning("a stop pressed while the page closes was not sent")
            return None
        future.add_done_callback(_log_press_failure)
        return future

    def shutdown(self) -> None:
        self.quitting.set()
        self._pool.shutdown(wait=False, cancel_futures=True)
        self._urgent.shutdown(wait=False, cancel_futures=True)
        self._presses.shutdown(wait=False, cancel_futures=True)


def _log_press_failure(done: Future[object]) -> None:
    error = None if done.cancelled() else done.exception()
    if error is not None:
        log.error("a stop button's press failed", exc_info=error)


def client_id(client: viser.ClientHandle | None) -> int | None:
    """The browser's id, None for an internal caller (a test, the server's own panel)."""
    return client.client_id if client is not None else None


def add_freeze_button(target: GuiTarget, runner: CommandRunner) -> viser.GuiButtonHandle:
    """The red Freeze button, above everything else, and the Esc key anywhere on the page: the button
    scrolls away with a long tab, the key does not."""
    button = target.gui.add_button(
        "Freeze",
        color="red",
        icon=viser.Icon.HAND_STOP,
        order=-1000.0,
        hint=f"Stop the arm where it is ({FREEZE_HOTKEY_LABEL} anywhere on the page)",
    )
    button.on_click(on_stop_press(runner, lambda client: freeze(runner, client)))
    hotkey = target.gui.add_command(
        "Freeze", description="Stop the arm where it is", hotkey=FREEZE_HOTKEY, icon=viser.Icon.HAND_STOP
    )
    hotkey.on_trigger(
        on_stop_press(runner, lambda client: freeze(runner, client, f"Freeze ({FREEZE_HOTKEY_LABEL})"))
    )
    return button


def freeze(runner: CommandRunner, client: viser.ClientHandle | None, label: str = "Freeze") -> Future[object]:
    """Every browser may stop the arm, and it never waits behind another command."""
    return runner.submit(label, lambda c: c.freeze(), client, urgent=True)


def add_robot_commands(target: GuiTarget, runner: CommandRunner) -> dict[str, viser.GuiButtonHandle]:
    """Home, Relax and Pack (Recover is in the banner under Freeze, where the error shows)."""
    actions: dict[str, Callable[[Controller], object]] = {
        "Home": lambda c: c.set_pose(
            Pose(angles=list(HOME_POSE_DEG)), MotionParams(speed=HOME_SPEED_PERCENT)
        ),
        "Relax": lambda c: c.relax(),
        "Pack": lambda c: c.pack(),
    }
    buttons: dict[str, viser.GuiButtonHandle] = {}
    for label, action in actions.items():
        button = target.gui.add_button(label)
        button.on_click(
            lambda event, label=label, action=action: runner.submit(label, action, event.client, motion=True)
        )
        buttons[label] = button
    return buttons
