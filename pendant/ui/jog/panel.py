"""The jog panel: frame, step and speed, and the jog pad (one row per axis: -, the live value, +)."""

from __future__ import annotations

import asyncio
import logging
import math
import threading
import time
from collections.abc import Callable

import numpy as np
import viser

from pendant.controller import ControllerError
from pendant.jog import JogFrame, Jogger, JogRefused, JogRequest
from pendant.kinematics import ArmModel
from pendant.ui.jog.pad import (
    axis_name,
    axis_values,
    cap_line,
    render_note,
    render_pad,
    render_values,
    tcp_capped_joint_speeds,
)
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.hold_line import HoldLine
from pendant.ui.kit.readout_rates import readout_period_s
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.kit.typed_field import FieldInvalid, NumberField

log = logging.getLogger(__name__)

CONTINUOUS = "Continuous"
STEP_CHOICES = (CONTINUOUS, "0.1", "1", "10")  # mm for X Y Z, degrees for joints and rotations
DEFAULT_SPEED_PERCENT = 10.0
HOLD_CONFIRM_HZ = 20.0  # four confirmations inside one deadman period
REFUSAL_REPEAT_S = 2.0  # a held button is refused once per press, not 20 times a second


def button_label(frame: JogFrame, axis: int, direction: int) -> str:
    return f"{axis_name(frame, axis)}{'+' if direction > 0 else '-'}"


class JogPanel:
    """The pad's buttons are the page's own (see jog_pad.py and client_page.js); each sends the hold and
    click messages of a hidden viser button here: "J1-" ... "J6+" for joints, "X-" ... "Yaw+" for Base/Tool,
    and "Stop jog" for a press the page cancelled (a swipe), which must stop and never step."""

    def __init__(
        self,
        target: GuiTarget,
        jogger: Jogger,
        runner: CommandRunner,
        arm: ArmModel,
        current_tool: Callable[[], np.ndarray],
        line: HoldLine | None = None,
    ) -> None:
        self._jogger = jogger
        self._runner = runner
        self._arm = arm
        self._current_tool = current_tool
        self.buttons: dict[tuple[int, int], viser.GuiButtonHandle] = {}
        for axis in range(6):
            for direction in (-1, +1):
                button = target.gui.add_button(button_label(JogFrame.JOINT, axis, direction), visible=False)
                self.buttons[(axis, direction)] = button
                self._bind(button, axis, direction)
        self.stop = target.gui.add_button("Stop jog", visible=False)
        self.stop.on_click(lambda _: self._cancelled())
        # The pad first, its settings under it: all six rows fit a 1024x768 screen with the status above.
        self.pad = target.gui.add_html("")  # rebuilt only with the frame or the role (see pad.py)
        self.values = target.gui.add_html("")  # the live values, put in the pad's labels in place
        self.note = target.gui.add_html("")  # when the 250 mm/s TCP limit slows a joint jog
        self.frame = target.gui.add_dropdown("Frame", [f.value for f in JogFrame], initial_value="Joint")
        self.step = target.gui.add_dropdown("Step (mm / °)", STEP_CHOICES, initial_value=CONTINUOUS)
        self.speed = NumberField(
            target.gui, "Speed %", DEFAULT_SPEED_PERCENT, low=1.0, high=100.0, decimals=0
        )
        self._snapshot = Snapshot(taken_at=0.0)
        self._pad_key: tuple[JogFrame, bool] | None = None
        self._locked = False
        self._shown_at = -math.inf
        self._refused_at = -math.inf
        self._told_stop = False  # this press's stop was told to the page (once per press)
        # A browser's own pad: its holds may come over the hold line (hold_line.py), under this key.
        self._client = target if isinstance(target, viser.ClientHandle) else None
        self._line = line if self._client is not None else None
        self._line_key = self._line.register(self) if self._line is not None else ""
        self._line_busy = threading.Lock()  # one controller conversation of this pad's queued at a time
        self.frame.on_update(lambda _: self._relabel())
        self.speed.on_commit(lambda _: self._render())
        self._render()

    @property
    def locked(self) -> bool:
        return self._locked

    @locked.setter
    def locked(self, locked: bool) -> None:
        if locked != self._locked:
            self._locked = locked
            self._render()

    def request(self, axis: int, direction: int) -> JogRequest:
        """The jog these controls ask for; JogRefused when a value is not one the page offers (a modified
        page can send any frame, step or speed: the server checks them, not the browser)."""
        if self.frame.value not in {f.value for f in JogFrame}:
            raise JogRefused(f"Jog frame must be one of {', '.join(f.value for f in JogFrame)}")
        if self.step.value not in STEP_CHOICES:
            raise JogRefused(f"Jog step must be one of {', '.join(STEP_CHOICES)} (mm or °)")
        frame = JogFrame(self.frame.value)
        step: float | None = None
        if self.step.value != CONTINUOUS:
            amount = float(self.step.value)
            step = amount / 1000.0 if frame is not JogFrame.JOINT and axis < 3 else math.radians(amount)
        try:
            speed = self.speed.value
        except FieldInvalid as error:  # empty or letters: no jog at a speed the operator did not type
            raise JogRefused(error.message) from None
        return JogRequest(frame, axis, direction, speed, step)

    def show(self, snapshot: Snapshot) -> None:
        """The live values (at most as often as readout_rates.py says: a viewer's pad is greyed out)."""
        self._snapshot = snapshot
        if time.monotonic() - self._shown_at >= readout_period_s(self._locked):
            self._render()

    def _render(self) -> None:
        frame = JogFrame(self.frame.value)
        note = ""
        if frame is JogFrame.JOINT and self._snapshot.q is not None:
            speed = self.speed.parse() if self.speed.reason is None else DEFAULT_SPEED_PERCENT
            note = cap_line(tcp_capped_joint_speeds(self._arm, self._snapshot.q, self._current_tool(), speed))
        uuids = {key: button._impl.uuid for key, button in self.buttons.items()}
        values = axis_values(frame, self._snapshot)
        self._shown_at = time.monotonic()
        shown = render_values(values)
        if shown != self.values.content:
            self.values.content = shown
        note_html = render_note(note)
        if note_html != self.note.content:
            self.note.content = note_html
        key = (frame, self._locked)
        if key != self._pad_key:  # not on a value: the pad's buttons keep their focus (see pad.py)
            self._pad_key = key
            line = f"{self._line.port} {self._line_key}" if self._line is not None else ""
            self.pad.content = render_pad(
                frame, values, uuids, self.stop._impl.uuid, disabled=self._locked, line=line
            )

    def close(self) -> None:
        """The browser left: its key opens the line no more."""
        if self._line is not None:
            self._line.forget(self._line_key)

    # --- the hold line (its connection's thread): never waits for viser's loop nor its callback pool -----
    def held(self, uuid: str) -> None:
        """A confirmation: the deadman hears it now; the controller is asked on the line's worker."""
        button = self._button(uuid)
        if button is None or self._line is None:
            return
        axis, direction = button
        releases = self._jogger.releases  # read in the line's order: a later release makes this one stale
        holder = self._client.client_id if self._client is not None else None
        self._jogger.still_held(releases, holder)
        if not self._line_busy.acquire(blocking=False):
            return  # the previous one is still queued or talking: this one has confirmed, that is enough

        def work() -> None:
            try:
                self._hold(self._client, axis, direction, releases)
            finally:
                self._line_busy.release()

        self._line.work(work)

    def let_go(self, uuid: str) -> None:
        """The press's release (a click) or its cancel ("Stop jog"), in order after its confirmations."""
        if uuid == self.stop._impl.uuid:
            self._cancelled()
            return
        button = self._button(uuid)
        if button is not None:
            self._clicked(self._client, *button)

    def _button(self, uuid: str) -> tuple[int, int] | None:
        for key, button in self.buttons.items():
            if button._impl.uuid == uuid:
                return key
        return None

    def _relabel(self) -> None:
        if self.frame.value not in {f.value for f in JogFrame}:
            return  # a forged frame: the jog itself is refused (request())
        frame = JogFrame(self.frame.value)
        for (axis, direction), button in self.buttons.items():
            button.label = button_label(frame, axis, direction)
        self._render()

    def _refused(self, client: viser.ClientHandle | None, label: str) -> bool:
        """Whether the page may not jog now; says so once per press."""
        now = time.monotonic()
        if now - self._refused_at < REFUSAL_REPEAT_S:
            if client is None:
                return False
            return self._runner.gate(client) is not None or self._runner.motion_block() is not None
        refused = self._runner.refusal(client, label, motion=True) is not None
        if refused:
            self._refused_at = now
        return refused

    def _hold(self, client: viser.ClientHandle | None, axis: int, direction: int, releases: int) -> None:
        label = (
            button_label(JogFrame(self.frame.value), axis, direction)
            if self.frame.value in {f.value for f in JogFrame}
            else f"Jog axis {axis + 1}"
        )
        try:
            request = self.request(axis, direction)
            if request.step is not None or self._refused(client, request.label()):
                return
            holder = client.client_id if client is not None else None
            if not self._jogger.hold(request, releases, holder):
                self._tell_stop(client, label, self._jogger.latch_cause(holder))
        except ControllerError as error:  # JogRefused (forged values) included
            self._told_stop = True  # the refusal says why: no second message for the same press
            if time.monotonic() - self._refused_at >= REFUSAL_REPEAT_S:
                self._refused_at = time.monotonic()
                notify_refusal(client, f"{label} refused", self._runner.explain(error.message))

    def _cancelled(self) -> None:
        self._told_stop = False
        self._jogger.release("released")

    def _tell_stop(self, client: viser.ClientHandle | None, label: str, cause: str | None) -> None:
        """Say "J1+ stopped: Collision detected: the arm would touch 'Box 1'" (the Target tab's words for
        that pose), once a press (the button stays down after it)."""
        if cause is None or self._told_stop:
            return
        self._told_stop = True
        notify_refusal(client, "Jog stopped", f"{label} stopped: {cause}")

    def _bind(self, button: viser.GuiButtonHandle, axis: int, direction: int) -> None:
        @button.on_hold(callback_hz=HOLD_CONFIRM_HZ)
        async def _(event: viser.GuiEvent) -> None:
            # Here, on viser's event loop, the page's messages arrive in the order it sent them: note how
            # many releases came before this confirmation, then talk to the controller on a thread.
            releases = self._jogger.releases
            self._jogger.still_held(releases, event.client_id)  # the deadman hears it now, not after the hop
            future = asyncio.get_running_loop().run_in_executor(
                None, self._hold, event.client, axis, direction, releases
            )
            future.add_done_callback(_log_failure)

        @button.on_click
        def _(event: viser.GuiEvent) -> None:
            self._clicked(event.client, axis, direction)

    def _clicked(self, client: viser.ClientHandle | None, axis: int, direction: int) -> None:
        self._refused_at = -math.inf  # a press ended: the next one is told its refusal again
        self._told_stop = False
        try:
            if self.step.value == CONTINUOUS:  # the click arrives on release: stop at once, whatever
                self._jogger.release("released")  # else the page sent
                return
            request = self.request(axis, direction)
            if self._runner.refusal(client, request.label(), motion=True) is None and not (
                self._jogger.step(request)
            ):
                notify_refusal(client, request.label(), "Cannot move further that way")
        except ControllerError as error:
            label = self.buttons[(axis, direction)].label
            notify_refusal(client, f"{label} refused", self._runner.explain(error.message))


def _log_failure(future: asyncio.Future[None]) -> None:
    if not future.cancelled() and future.exception() is not None:
        log.error("jog hold failed", exc_info=future.exception())
