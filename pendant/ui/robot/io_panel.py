"""Digital outputs (toggles read back from the controller), inputs, and the gripper."""

from __future__ import annotations

import viser

from pendant.controller import Controller, SignalLevel
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS, INPUT_PORTS, OUTPUT_PORTS
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.snapshot import Snapshot


class IoPanel:
    """DO toggles follow what the controller reports, so a refused write springs back."""

    def __init__(self, target: GuiTarget, runner: CommandRunner) -> None:
        self._runner = runner
        self._syncing = False
        self.outputs: dict[int, viser.GuiCheckboxHandle] = {}
        for port in OUTPUT_PORTS:
            toggle = target.gui.add_checkbox(f"DO{port}", initial_value=False)
            self.outputs[port] = toggle
            toggle.on_update(lambda event, port=port: self._write_output(port, event))
        self.inputs = {
            port: target.gui.add_checkbox(f"DI{port}", initial_value=False, disabled=True)
            for port in INPUT_PORTS
        }
        self.gripper_open = target.gui.add_button("Open gripper", icon=viser.Icon.ARROWS_HORIZONTAL)
        self.gripper_close = target.gui.add_button("Close gripper", icon=viser.Icon.ARROWS_MINIMIZE)
        self.gripper_open.on_click(
            lambda e: runner.submit(
                "Open gripper", lambda c: c.open_gripper(DEFAULT_GRIPPER_TIMEOUT_MS), e.client, motion=True
            )
        )
        self.gripper_close.on_click(
            lambda e: runner.submit(
                "Close gripper", lambda c: c.close_gripper(DEFAULT_GRIPPER_TIMEOUT_MS), e.client, motion=True
            )
        )

    def show(self, snapshot: Snapshot) -> None:
        self._syncing = True
        try:
            for port, level in snapshot.outputs.items():
                high = level is SignalLevel.HIGH
                if self.outputs[port].value != high:
                    self.outputs[port].value = high
            for port, level in snapshot.inputs.items():
                high = level is SignalLevel.HIGH
                if self.inputs[port].value != high:
                    self.inputs[port].value = high
        finally:
            self._syncing = False

    def _write_output(self, port: int, event: viser.GuiEvent) -> None:
        if self._syncing or event.client is None:
            return  # our own read-back, not an operator's click
        high = bool(self.outputs[port].value)
        level = SignalLevel.HIGH if high else SignalLevel.LOW

        def write(controller: Controller) -> None:
            try:
                controller.set_output(port, level)
            except Exception:
                self._spring_back(port, high)
                raise

        future = self._runner.submit(f"DO{port} {level.value}", write, event.client)
        if future.done() and not future.cancelled() and future.exception() is not None:
            self._spring_back(port, high)  # refused by the page (a viewer), never sent

    def _spring_back(self, port: int, asked_high: bool) -> None:
        """Show a refused write as not done: the read-back cannot correct the toggle while the controller
        does not answer (emergency, no response)."""
        toggle = self.outputs[port]
        if toggle.value == asked_high:  # not clicked again meanwhile
            toggle.value = not asked_high  # from Python: no client, so not sent to the controller
