"""The pendant's web UI: a viser server showing the arm live, with status, jogging, targets, IO and settings."""

from __future__ import annotations

import threading
import time
from dataclasses import replace

import viser

from pendant.controller import Controller, ControllerError
from pendant.jog import Jogger
from pendant.kinematics import ArmModel
from pendant.sim import SimController
from pendant.ui.commands import CommandRunner, add_freeze_button, add_robot_commands
from pendant.ui.io_panel import IoPanel
from pendant.ui.jog_panel import JogPanel
from pendant.ui.scene import ArmScene
from pendant.ui.settings_panel import SettingsPanel
from pendant.ui.sim_panel import SimPanel
from pendant.ui.snapshot import Snapshot, read_snapshot
from pendant.ui.status_panel import StatusPanel
from pendant.ui.target_panel import TargetPanel

REFRESH_HZ = 30.0
IO_EVERY_N_TICKS = 6  # IO and tool change rarely: read them at 5 Hz


class PendantUI:
    """Serves the page on `host:port` and keeps it in step with `controller` until `stop()`."""

    def __init__(self, controller: Controller, arm: ArmModel, *, host: str, port: int, mode_line: str) -> None:
        self.controller = controller
        self.arm = arm
        self.server = viser.ViserServer(host=host, port=port, label="PULSE pendant", verbose=False)
        self.server.gui.configure_theme(control_width="large", show_logo=False)
        self.runner = CommandRunner(controller)
        self.jogger = Jogger(controller, arm)
        self.latest = Snapshot(taken_at=0.0)
        gui = self.server.gui

        self.freeze = add_freeze_button(self.server, self.runner)
        self.status = StatusPanel(self.server, mode_line)
        tabs = gui.add_tab_group()
        with tabs.add_tab("Jog", viser.Icon.ARROWS_MOVE):
            self.jog = JogPanel(self.server, self.jogger)
        with tabs.add_tab("Target", viser.Icon.TARGET):
            self.target = TargetPanel(self.server, arm, self.runner, lambda: self.latest.q)
        with tabs.add_tab("IO", viser.Icon.PLUG):
            self.io = IoPanel(self.server, self.runner)
        with tabs.add_tab("Robot", viser.Icon.ROBOT):
            self.buttons = add_robot_commands(self.server, self.runner)
            self.settings = SettingsPanel(self.server, self.runner)
        if isinstance(controller, SimController):
            with tabs.add_tab("Simulator", viser.Icon.FLASK):
                self.sim_panel = SimPanel(self.server, controller, self.runner)
        self.scene = ArmScene(self.server, arm.urdf_path)
        self._robot_id = self._read_quietly(controller.get_robot_id, "")
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._refresh_loop, name="pendant-refresh", daemon=True)

    def start(self) -> PendantUI:
        self.refresh()
        self.target.reset_to_current()
        self.jogger.start_watchdog()
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        self.jogger.stop_watchdog()
        self.runner.shutdown()
        self.server.stop()

    def refresh(self, *, with_io: bool = True) -> Snapshot:
        """Read the controller once and show what it says (IO and tool only when `with_io`)."""
        tool_name = self.latest.tool_name
        if with_io:
            tool_name = self._read_quietly(lambda: self.controller.get_tool().name, tool_name)
        snapshot = read_snapshot(self.controller, with_io=with_io, robot_id=self._robot_id, tool_name=tool_name)
        if not with_io:
            snapshot = replace(snapshot, outputs=self.latest.outputs, inputs=self.latest.inputs)
        if snapshot.q is not None:
            self.scene.show(snapshot.q, snapshot.gripper_opening, self.arm.fk(snapshot.q))
        self.latest = snapshot
        self.status.show(snapshot)
        if with_io:
            self.io.show(snapshot)
        return snapshot

    def _refresh_loop(self) -> None:
        period = 1.0 / REFRESH_HZ
        tick = 0
        next_at = time.monotonic()
        while not self._stop.is_set():
            self.refresh(with_io=tick % IO_EVERY_N_TICKS == 0)
            tick += 1
            next_at += period
            self._stop.wait(max(0.0, next_at - time.monotonic()))
            next_at = max(next_at, time.monotonic() - period)  # after a stall, do not race to catch up

    @staticmethod
    def _read_quietly(read, default):  # type: ignore[no-untyped-def]
        try:
            return read()
        except ControllerError:
            return default
