"""Simulator only: set the digital inputs, inject faults, reset (asked first: it forgets the arm's state)."""

from __future__ import annotations

import viser

from pendant.controller import SignalLevel
from pendant.controller.types import INPUT_PORTS
from pendant.sim import Fault, SimController
from pendant.sim.fault_kinds import FAULT_KINDS
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.confirm import Confirmation
from pendant.ui.kit.gui_target import GuiTarget

# The fault kinds table's buttons.
FAULT_LABELS: dict[Fault, str] = {
    kind.fault: kind.label for kind in FAULT_KINDS if kind.fault is not None and kind.label is not None
}


class SimPanel:
    def __init__(self, target: GuiTarget, sim: SimController, runner: CommandRunner) -> None:
        self._sim = sim
        self._runner = runner
        self.inputs = {}
        for port in INPUT_PORTS:
            switch = target.gui.add_checkbox(f"Set DI{port}", initial_value=False)
            switch.on_update(
                lambda event, port=port, switch=switch: self._set_input(port, switch.value, event)
            )
            self.inputs[port] = switch
        self.faults = {}
        for fault, label in FAULT_LABELS.items():
            button = target.gui.add_button(label, color="orange")
            button.on_click(
                lambda e, fault=fault: runner.submit(
                    f"Inject {fault.value}", lambda _: sim.inject_fault(fault), e.client
                )
            )
            self.faults[fault] = button
        self.reset = target.gui.add_button("Reset simulator", icon=viser.Icon.REFRESH)
        self.confirmation = Confirmation(target)
        self.reset.on_click(
            lambda _: self.confirmation.ask(
                "Reset the simulator? The arm goes home; IO, faults, tool and base go back to power-on.",
                lambda client: runner.submit("Reset", lambda _: self._reset(sim), client),
            )
        )

    def _set_input(self, port: int, high: bool, event: viser.GuiEvent) -> None:
        level = SignalLevel.HIGH if high else SignalLevel.LOW
        self._runner.submit(
            f"DI{port} {level.value}", lambda _: self._sim.set_input(port, level), event.client
        )

    def _reset(self, sim: SimController) -> None:
        sim.reset()
        for switch in self.inputs.values():
            switch.value = False
