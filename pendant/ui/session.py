"""One browser's view of the pendant: its own panels, built on its own GUI, fed by the shared state."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import viser

from pendant.controller import Controller
from pendant.jog import Jogger
from pendant.kinematics import ArmModel
from pendant.sim import SimController
from pendant.ui.commands import CommandRunner, add_freeze_button, add_robot_commands
from pendant.ui.gui_target import GuiTarget
from pendant.ui.io_panel import IoPanel
from pendant.ui.jog_panel import JogPanel
from pendant.ui.settings_panel import SettingsPanel
from pendant.ui.sim_panel import SimPanel
from pendant.ui.snapshot import Snapshot
from pendant.ui.status_panel import StatusPanel
from pendant.ui.target_panel import TargetPanel


class ClientSession:
    """Freeze on top, the status, then tabs: Jog, Target, IO, Robot (and Simulator in simulator mode)."""

    def __init__(
        self,
        target: GuiTarget,
        *,
        controller: Controller,
        arm: ArmModel,
        runner: CommandRunner,
        jogger: Jogger,
        mode_line: str,
        current_q: Callable[[], np.ndarray | None],
    ) -> None:
        self.target = target
        self.freeze = add_freeze_button(target, runner)
        self.status = StatusPanel(target, mode_line)
        self.tabs = target.gui.add_tab_group()
        with self.tabs.add_tab("Jog", viser.Icon.ARROWS_MOVE):
            self.jog = JogPanel(target, jogger, runner)
        with self.tabs.add_tab("Target", viser.Icon.TARGET):
            self.target_panel = TargetPanel(target, arm, runner, current_q)
        with self.tabs.add_tab("IO", viser.Icon.PLUG):
            self.io = IoPanel(target, runner)
        with self.tabs.add_tab("Robot", viser.Icon.ROBOT):
            self.robot_buttons = add_robot_commands(target, runner)
            self.settings = SettingsPanel(target, runner)
        self.sim_panel: SimPanel | None = None
        if isinstance(controller, SimController):
            with self.tabs.add_tab("Simulator", viser.Icon.FLASK):
                self.sim_panel = SimPanel(target, controller, runner)
        self.target_panel.reset_to_current()

    def show(self, snapshot: Snapshot, *, with_io: bool) -> None:
        self.status.show(snapshot)
        if with_io:
            self.io.show(snapshot)
