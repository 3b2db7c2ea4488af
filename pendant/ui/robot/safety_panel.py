"""The arm's safety state: its system state (`/status`, shown in the status line), the Robot tab's
stop-on-input binding, free drive and identity, and the Dashboard's failure list. The protective Stop and
Recover: under the status and in the banner (page/status_panel.py, page/banner.py)."""

from __future__ import annotations

import html
from collections.abc import Sequence
from concurrent.futures import Future

import viser

from pendant.controller import Controller, ControllerError, SignalLevel
from pendant.controller.errors import Unsupported
from pendant.controller.system_types import Failure, FailureLevel, SystemState
from pendant.controller.types import INPUT_PORTS
from pendant.ui.kit.availability import Availability
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset

SYSTEM_STATE_COLOURS = {
    SystemState.ACTIVE: "#237032",
    SystemState.MOTION: "#1971c2",
    SystemState.JOGGING: "#1971c2",
    SystemState.ZERO_GRAVITY: "#9c36b5",
    SystemState.INITIALIZING: "#868e96",
    SystemState.TWISTED: "#b8420c",
    SystemState.INITIALIZATION_FAILURE: "#e03131",
    SystemState.BROKEN: "#c92a2a",
    SystemState.EMERGENCY: "#c92a2a",
}
LEVEL_COLOURS = {FailureLevel.FATAL: "#c92a2a", FailureLevel.ERROR: "#e03131", FailureLevel.WARN: "#b8420c"}
FAILURES_SHOWN = 20
PROTECTIVE_STOP_HINT = "Protective stop: the arm stops and holds; Recover leaves it"


def render_system_state(state: CellState) -> str:
    """The system state as a fragment of the status line (`/status`), or why the controller has none."""
    if "status" in state.unsupported:
        return '<span id="system-state" style="color:#868e96">system state: not on this controller</span>'
    value = state.system_state
    label = value.value if value is not None else "unknown"
    colour = SYSTEM_STATE_COLOURS.get(value, "#868e96") if value is not None else "#868e96"
    return f'<span id="system-state">system <b style="color:{colour}">{label}</b></span>'


def render_failures(failures: Sequence[Failure], unsupported: str | None) -> str:
    if unsupported:
        return inset(f'<div style="color:#868e96">Failures unavailable: {html.escape(unsupported)}</div>')
    if not failures:
        return inset('<div id="failures">No failures reported.</div>')
    rows = "".join(
        f'<tr><td>{html.escape(f.date)}</td><td style="color:{LEVEL_COLOURS.get(f.level, "#495057")}">'
        f"{f.level.value}</td><td>{f.type.value}</td><td>{html.escape(f.message)}</td></tr>"
        for f in list(failures)[-FAILURES_SHOWN:][::-1]
    )
    return inset(
        '<table id="failures" style="width:100%;font-size:0.8em"><tr><th>Time</th><th>Level</th>'
        f"<th>Type</th><th>Message</th></tr>{rows}</table>"
    )


def read_identity(controller: Controller) -> str:
    """`/robot/info` and `/version/*` as markdown; what the controller lacks is said, not raised."""
    lines: list[str] = []
    reads = (
        ("Robot", lambda: _fields(controller.get_robot_info().model_dump())),
        ("Hardware", lambda: _fields(controller.get_hardware_version().model_dump())),
        ("Software", lambda: _fields(controller.get_software_version().model_dump())),
        ("Robot software", controller.get_robot_software_version),
    )
    for label, read in reads:
        try:
            lines.append(f"**{label}:** {read()}")
        except Unsupported:
            lines.append(f"**{label}:** not reported by this controller (older firmware)")
        except ControllerError as error:
            lines.append(f"**{label}:** unavailable ({error.message})")
    return "  \n".join(lines)


def _fields(data: dict[str, object]) -> str:
    return ", ".join(
        f"{key} {', '.join(map(str, value)) if isinstance(value, list) else value}"
        for key, value in data.items()
    )


class RobotSafetyPanel:
    """Robot tab: bind the protective stop to an input level, free drive, and what the arm is."""

    def __init__(self, target: GuiTarget, runner: CommandRunner) -> None:
        self._runner = runner
        gui = target.gui
        with gui.add_folder("Protective stop on input", expand_by_default=False):
            self.stop_port = gui.add_dropdown(
                "Input", options=[f"DI{p}" for p in INPUT_PORTS], initial_value=f"DI{INPUT_PORTS[0]}"
            )
            self.stop_level = gui.add_dropdown("Level", options=["HIGH", "LOW"], initial_value="HIGH")
            self.bind = gui.add_button("Bind stop")
            self.unbind = gui.add_button("Unbind stop")
            stop_controls = (self.stop_port, self.stop_level, self.bind, self.unbind)
            self.input_stop = Availability(gui, "Stop on input", stop_controls)
        self.free_drive = gui.add_checkbox(
            "Free drive", initial_value=False, hint="Zero gravity: move the arm by hand"
        )
        self.free_drive_availability = Availability(gui, "Free drive", (self.free_drive,))
        with gui.add_folder("Robot identity", expand_by_default=False):
            self.identity = gui.add_markdown("Reading the controller…")
        self.bind.on_click(lambda e: self.bind_stop(e.client))
        self.unbind.on_click(
            lambda e: self.input_stop.learn(runner.submit("Unbind stop", lambda c: c.unbind_stop(), e.client))
        )
        self._syncing = False
        self.free_drive.on_update(
            lambda e: None if self._syncing else self.set_free_drive(self.free_drive.value, e.client)
        )

    def set_locked(self, locked: bool) -> None:
        """A viewer's page, or a controller without these operations: greyed out."""
        self.input_stop.set_locked(locked)
        self.free_drive_availability.set_locked(locked)

    def bind_stop(self, client: viser.ClientHandle | None = None) -> Future[object]:
        port = int(str(self.stop_port.value).removeprefix("DI"))
        level = SignalLevel(self.stop_level.value)
        return self.input_stop.learn(
            self._runner.submit(
                f"Bind stop to DI{port} {level.value}", lambda c: c.bind_stop(port, level), client
            )
        )

    def set_free_drive(self, on: bool, client: viser.ClientHandle | None = None) -> Future[object]:
        label, action = ("Free drive on", _zg_on) if on else ("Free drive off", _zg_off)
        future = self._runner.submit(label, action, client)
        # A refused switch springs back before the control is greyed out for a missing feature: whoever sees
        # it greyed sees it off (the arm is not in free drive).
        future.add_done_callback(lambda f: self._show_free_drive(not on) if f.exception() else None)
        return self.free_drive_availability.learn(future)

    def _show_free_drive(self, on: bool) -> None:
        """The toggle as the controller has it (a refused switch springs back)."""
        if self.free_drive.value != on:
            self._syncing = True
            try:
                self.free_drive.value = on
            finally:
                self._syncing = False

    def show(self, state: CellState, identity: str) -> None:
        if identity and self.identity.content != identity:
            self.identity.content = identity
        # Free drive (/zg) and the input stop (/stop/bind) came with SDK 1.8's /status: a controller that
        # answers 404 to /status lacks them too (and a 404 to the command itself says so as well).
        status = state.unsupported.get("status")
        older = f"this controller has no SDK 1.8 safety operations ({status})" if status else None
        self.input_stop.show(older)
        self.free_drive_availability.show(older)
        if state.system_state is not None:
            self._show_free_drive(state.system_state is SystemState.ZERO_GRAVITY)


def _zg_on(c: Controller) -> object:
    return c.zg_on()


def _zg_off(c: Controller) -> object:
    return c.zg_off()
