"""One browser's view of the pendant: its own panels, built on its own GUI, fed by the shared state."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
import viser

from pendant.access.remote import RemoteControl
from pendant.cell.geometry import CellModel
from pendant.controller import Controller, MotionStatus
from pendant.eventlog import EventLog
from pendant.jog import Jogger
from pendant.kinematics import ArmModel
from pendant.program import ProgramWorkspace
from pendant.sim import SimController
from pendant.teach.recording import PathRecorder
from pendant.telemetry import Telemetry
from pendant.ui.cell.panel import CellPanel
from pendant.ui.dashboard.events import EventsRenderer
from pendant.ui.dashboard.join_qr import add_join_button
from pendant.ui.dashboard.panel import DashboardPanel
from pendant.ui.dashboard.plots import PlotSource
from pendant.ui.jog.panel import JogPanel
from pendant.ui.jog.record_panel import RecordPanel
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner, add_freeze_button, add_robot_commands
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.hold_line import HoldLine
from pendant.ui.kit.jobs import PageJobs
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.kit.view_only import ViewOnly
from pendant.ui.page.banner import Banner
from pendant.ui.page.recovery import Recovery
from pendant.ui.page.roles import ControlDesk, ControlPanel
from pendant.ui.page.status_panel import StatusPanel
from pendant.ui.page.teach_bar import TeachBar
from pendant.ui.page.view_fit import ViewFit
from pendant.ui.program.panel import ProgramPanel
from pendant.ui.robot.io_panel import IoPanel
from pendant.ui.robot.safety_panel import RobotSafetyPanel, render_failures
from pendant.ui.robot.settings_panel import SettingsPanel
from pendant.ui.robot.sim_panel import SimPanel
from pendant.ui.robot.tool_shape_panel import ToolShapePanel
from pendant.ui.scene.ghost_stage import GhostStage
from pendant.ui.target.hand_guide import HandGuide
from pendant.ui.target.panel import TargetPanel

RecordingListener = Callable[[viser.ClientHandle | None, str], None]


def _set_disabled(handle: viser.GuiInputHandle, disabled: bool) -> None:
    if isinstance(handle, viser.GuiButtonGroupHandle):  # viser cannot disable these: hide them instead
        if handle.visible == disabled:
            handle.visible = not disabled
    elif handle.disabled != disabled:  # each assignment is a message to the browser
        handle.disabled = disabled


class ClientSession:
    """Freeze on top, the status and the control line, then tabs: Jog, Target, Program, IO, Robot (and
    Simulator in simulator mode), Dashboard.

    A viewer's session has every motion, IO and settings control disabled (Freeze never is); the server
    refuses their commands anyway (see roles.ControlDesk). `client_id` None: panels built on the server's
    own GUI (headless tests), never locked.
    """

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
        current_tool: Callable[[], np.ndarray],
        desk: ControlDesk,
        telemetry: Telemetry,
        events: EventLog,
        programs: ProgramWorkspace,
        client_id: int | None = None,
        url_token: str | None = None,
        remote: RemoteControl | None = None,
        on_recording: RecordingListener | None = None,
        join_urls: list[str] | None = None,
        current_cell: Callable[[], CellModel | None] = lambda: None,
        cell_state: Callable[[], CellState] = CellState,
        cells_dir: Path = Path("cells"),
        recorder: PathRecorder | None = None,
        recovery: Recovery | None = None,
        freeze: viser.GuiButtonHandle | None = None,
        jobs: PageJobs | None = None,
        line: HoldLine | None = None,
    ) -> None:
        self.target = target
        self.client_id = client_id
        self._desk = desk
        # `freeze`: already on the page (sent the moment the browser connected, before its other panels)
        self.freeze = freeze if freeze is not None else add_freeze_button(target, runner)
        sim = controller if isinstance(controller, SimController) else None
        self.banner = (  # under Freeze: what is wrong and the way out (recovery.py)
            Banner(
                target, recovery, runner, programs, sim=sim, urdf_path=arm.urdf_path, cell_state=cell_state
            )
            if recovery is not None
            else None
        )
        self.status = StatusPanel(target, mode_line, runner, recover_in_banner=self.banner is not None)
        self.control = ControlPanel(target, desk, client_id, url_token, remote)
        self.ghosts = GhostStage(target)  # one ghost at a time in the view (or every one), and its legend
        self.tabs = target.gui.add_tab_group()
        with self.tabs.add_tab("Jog", viser.Icon.ARROWS_MOVE):
            self.jog = JogPanel(target, jogger, runner, arm, current_tool, line)
            # Right under the pad (before its settings): the Program tab's Record and Run, wired below.
            self.teach = TeachBar(
                target,
                programs,
                record=lambda client, gripper: self.program.record_here(client, gripper),
                run=lambda client: self.program.start_run("Run", client),
                order=self.jog.pad.order + 0.5,
            )
            self.record = RecordPanel(target, recorder or PathRecorder(), programs, runner)
            self.view_fit = (  # a browser's own camera: none on the server's shared GUI
                ViewFit(target, arm, current_q, current_tool, current_cell)
                if isinstance(target, viser.ClientHandle)
                else None
            )
            self.ghosts.add_switch()  # "Every ghost", by Fit view: what the view shows
        with self.tabs.add_tab("Target", viser.Icon.TARGET):
            self.target_panel = TargetPanel(
                target, arm, runner, current_q, current_tool, current_cell, ghosts=self.ghosts
            )
        with self.tabs.add_tab("Program", viser.Icon.LIST_NUMBERS):
            self.program = ProgramPanel(
                target, programs, runner, arm=arm, current_cell=current_cell, ghosts=self.ghosts
            )
        with self.tabs.add_tab("Cell", viser.Icon.BOX):
            self.cell = CellPanel(target, runner, cells_dir, cell_state)
        with self.tabs.add_tab("IO", viser.Icon.PLUG):
            self.io = IoPanel(target, runner)
        with self.tabs.add_tab("Robot", viser.Icon.ROBOT):
            self.robot_buttons = add_robot_commands(target, runner)
            self.settings = SettingsPanel(target, runner)
            self.tool_shape = ToolShapePanel(target, runner)
            self.robot_safety = RobotSafetyPanel(target, runner)
        self.sim_panel: SimPanel | None = None
        if isinstance(controller, SimController):
            self.target_panel.hand = HandGuide(controller, runner, lambda: cell_state().system_state)
            with self.tabs.add_tab("Simulator", viser.Icon.FLASK):
                self.sim_panel = SimPanel(target, controller, runner)
        with self.tabs.add_tab("Dashboard", viser.Icon.GAUGE):
            self.dashboard = DashboardPanel(
                target,
                telemetry,
                events,
                may_record=desk.gate,
                on_recording=on_recording if on_recording is not None else (lambda client, message: None),
                arm_urdf=arm.urdf_path,
                jobs=jobs if jobs is not None else PageJobs(),
                ghosts=self.ghosts,
            )
            self.join = add_join_button(target, join_urls) if join_urls else None
            self.failures = target.gui.add_html(render_failures((), None))
        self.target_panel.reset_to_current()
        self._operator_only: list[viser.GuiInputHandle] = list(self._commanding_handles())
        self._view_only = ViewOnly()
        self.locked = False
        self._failures_html = ""
        self.apply_role(desk.operator)

    def _commanding_handles(self) -> Iterable[viser.GuiInputHandle]:
        """Every control that moves the arm or changes IO or settings (Freeze is not one of them)."""
        if self.control.remote is not None:
            yield self.control.remote
        jog = self.jog
        yield from (
            self.status.recover,
            jog.frame,
            jog.step,
            jog.speed.handle,
            *jog.buttons.values(),
            jog.stop,
        )
        target = self.target_panel
        yield from (*(field.handle for field in target.joints), target.speed.handle, target.from_current)
        yield from self.program.commanding_handles()
        yield from self.io.outputs.values()
        yield from (self.io.gripper_open, self.io.gripper_close)
        yield from self.robot_buttons.values()
        yield from self.cell.controls
        yield from self.record.controls
        yield from self.teach.controls
        s = self.settings
        yield from (
            s.tool_name,
            s.tool_xyz.handle,
            s.tool_rpy.handle,
            s.tool_radius.handle,
            s.set_tool,
            s.base_xyz.handle,
            s.base_rpy.handle,
            s.set_base,
        )
        if self.sim_panel is not None:
            yield from (
                *self.sim_panel.inputs.values(),
                *self.sim_panel.faults.values(),
                self.sim_panel.reset,
            )

    def lock_with(self, *handles: viser.GuiInputHandle) -> None:
        """Add controls that only the operator may use (e.g. a panel wired in later)."""
        self._operator_only.extend(handles)
        for handle in handles:
            _set_disabled(handle, self.locked)

    def apply_role(self, operator: int | None) -> None:
        """Enable the commanding controls for the operator's browser, disable them for a viewer's."""
        self.locked = self.client_id is not None and operator != self.client_id
        for handle in self._operator_only:
            self._view_only.apply(handle, self.locked)  # greyed out, the tooltip saying why
        self.target_panel.locked = self.locked
        self.jog.locked = self.locked
        self.status.viewer = self.locked
        self.teach.set_locked(self.locked)
        self.cell.set_locked(self.locked)
        self.robot_safety.set_locked(self.locked)
        self.tool_shape.set_locked(self.locked)
        self.program.locked = self.locked
        ok = self.target_panel.executable
        _set_disabled(self.target_panel.move_j, self.locked or not ok)
        _set_disabled(self.target_panel.move_l, self.locked or not ok)
        self.control.show(operator)
        self.dashboard.show_recording(locked=self.locked)

    def close(self) -> None:
        """The browser left: stop following the shared program."""
        self.program.close()
        self.teach.close()
        self.dashboard.close()
        self.jog.close()

    def show(self, snapshot: Snapshot, *, with_io: bool) -> None:
        if self.banner is not None:
            self.banner.show()
        self.status.show(snapshot)
        self.jog.show(snapshot)
        if with_io:  # 5 Hz is enough for these, and spares every browser six sliders' worth of messages
            self.io.show(snapshot)
            self.target_panel.follow(snapshot.q, moving=snapshot.motion_status is MotionStatus.RUNNING)

    def show_cell(self, state: CellState, identity: str, *, cell_changed: bool) -> None:
        """What the controller reports of its cell and safety (a few times a second)."""
        self.status.show_system(state)
        self.cell.show(state)
        self.robot_safety.show(state, identity)
        self.tool_shape.show(state)
        self.record.show()
        if cell_changed:
            self.target_panel.recheck()
        failures = render_failures(state.failures, state.unsupported.get("failures"))
        if failures != self._failures_html:
            self.failures.content = failures
            self._failures_html = failures

    def show_dashboard(
        self, *, table_html: str | None, plots: PlotSource | None, events: EventsRenderer | None
    ) -> None:
        """The dashboard's shared renderings (None: nothing new of that kind)."""
        if table_html is not None:
            self.dashboard.show_table(table_html)
            self.dashboard.show_recording(locked=self.locked)
        if plots is not None:
            self.dashboard.show_plots(plots)
        if events is not None:
            self.dashboard.show_events(events)
