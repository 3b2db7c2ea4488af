"""Simulator only: set the digital inputs, inject faults, reset."""

from __future__ import annotations

import viser

from pendant.controller import SignalLevel
from pendant.controller.types import INPUT_PORTS
from pendant.sim import Fault, SimController
from pendant.ui.commands import CommandRunner

FAULT_LABELS = {Fault.ERROR: "Inject ERROR", Fault.EMERGENCY: "Inject EMERGENCY", Fault.NO_RESPONSE: "Inject no response"}


class SimPanel:
    def __init__(self, server: viser.ViserServer, sim: SimController, runner: CommandRunner) -> None:
        self.inputs = {}
        for port in INPUT_PORTS:
            switch = server.gui.add_checkbox(f"Set DI{port}", initial_value=False)
            switch.on_update(
                lambda _, port=port, switch=switch: sim.set_input(
                    port, SignalLevel.HIGH if switch.value else SignalLevel.LOW
                )
            )
            self.inputs[port] = switch
        self.faults = {}
        for fault, label in FAULT_LABELS.items():
            button = server.gui.add_button(label, color="orange")
            button.on_click(lambda e, fault=fault: runner.submit(f"Inject {fault.value}", lambda _: sim.inject_fault(fault), e.client))
            self.faults[fault] = button
        self.reset = server.gui.add_button("Reset simulator", icon=viser.Icon.REFRESH)
        self.reset.on_click(lambda e: runner.submit("Reset", lambda _: self._reset(sim), e.client))

    def _reset(self, sim: SimController) -> None:
        sim.reset()
        for switch in self.inputs.values():
            switch.value = False
