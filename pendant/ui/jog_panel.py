"""The jog panel: joint or Cartesian (Base/Tool) jog buttons, step size and speed."""

from __future__ import annotations

import math

import viser

from pendant.controller import ControllerError
from pendant.jog import JogFrame, Jogger, JogRefused, JogRequest
from pendant.jog.targets import CARTESIAN_AXES
from pendant.ui.commands import CommandRunner, notify_refusal
from pendant.ui.gui_target import GuiTarget

CONTINUOUS = "Continuous"
STEP_CHOICES = (CONTINUOUS, "0.1", "1", "10")  # mm for X Y Z, degrees for joints and rotations
DEFAULT_SPEED_PERCENT = 10.0
HOLD_CONFIRM_HZ = 20.0  # four confirmations inside one deadman period


def button_label(frame: JogFrame, axis: int, direction: int) -> str:
    name = f"J{axis + 1}" if frame is JogFrame.JOINT else CARTESIAN_AXES[axis]
    return f"{name}{'+' if direction > 0 else '-'}"


class JogPanel:
    """Buttons whose labels follow the frame: "J1-" ... "J6+" for joints, "X-" ... "Yaw+" for Base/Tool."""

    def __init__(self, target: GuiTarget, jogger: Jogger, runner: CommandRunner) -> None:
        self._jogger = jogger
        self._runner = runner
        self.frame = target.gui.add_dropdown("Frame", [f.value for f in JogFrame], initial_value="Joint")
        self.step = target.gui.add_dropdown("Step (mm / °)", STEP_CHOICES, initial_value=CONTINUOUS)
        self.speed = target.gui.add_slider(
            "Speed %", min=1.0, max=100.0, step=1.0, initial_value=DEFAULT_SPEED_PERCENT
        )
        self.buttons: dict[tuple[int, int], viser.GuiButtonHandle] = {}
        for axis in range(6):
            for direction in (-1, +1):
                button = target.gui.add_button(button_label(JogFrame.JOINT, axis, direction))
                self.buttons[(axis, direction)] = button
                self._bind(button, axis, direction)
        self.frame.on_update(lambda _: self._relabel())

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
        speed = self.speed.value
        if isinstance(speed, bool) or not isinstance(speed, int | float):
            raise JogRefused("Jog speed must be a number")
        return JogRequest(frame, axis, direction, float(speed), step)

    def _relabel(self) -> None:
        if self.frame.value not in {f.value for f in JogFrame}:
            return  # a forged frame: the jog itself is refused (request())
        frame = JogFrame(self.frame.value)
        for (axis, direction), button in self.buttons.items():
            button.label = button_label(frame, axis, direction)

    def _bind(self, button: viser.GuiButtonHandle, axis: int, direction: int) -> None:
        @button.on_hold(callback_hz=HOLD_CONFIRM_HZ)
        def _(event: viser.GuiEvent) -> None:
            try:
                request = self.request(axis, direction)
                if request.step is None and self._runner.refusal(event.client, request.label()) is None:
                    self._jogger.hold(request)
            except ControllerError as error:
                notify_refusal(event.client, f"{button.label} refused", error.message)

        @button.on_click
        def _(event: viser.GuiEvent) -> None:
            try:
                if self.step.value == CONTINUOUS:  # the click arrives on release: stop at once, whatever
                    self._jogger.release("released")  # else the page sent
                    return
                request = self.request(axis, direction)
                if self._runner.refusal(event.client, request.label()) is None and not self._jogger.step(
                    request
                ):
                    notify_refusal(event.client, request.label(), "Cannot move further that way")
            except ControllerError as error:
                notify_refusal(event.client, f"{button.label} refused", error.message)
