"""The pendant's web UI: one shared 3D scene, and for every browser its own panels (see session.py).

Many browsers may watch; one of them is the operator (roles.py). The refresh loop reads the controller for
everybody: the state at 30 Hz, the motors at 10 Hz into one shared history (the dashboard), and logs state
changes and errors to the event log.
"""

from __future__ import annotations

import contextlib
import logging
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import cast

import numpy as np
import viser

from pendant.access.origin import OriginPolicy
from pendant.access.remote import RemoteControl
from pendant.access.throttle import FailedAttempts
from pendant.cell.file import cells_dir
from pendant.cell.geometry import CellAwareArm, CellModel
from pendant.config import EnvironmentMap
from pendant.controller import Controller
from pendant.controller.stops import StopBus
from pendant.eventlog import EventLog
from pendant.kinematics import ArmModel
from pendant.monitoring import PendantMetrics
from pendant.monitoring import data_dir as resolve_data_dir
from pendant.teach.recording import PathRecorder
from pendant.telemetry import Telemetry, arm_drawing, recordings_dir
from pendant.ui.dashboard.arm_state import arm_state
from pendant.ui.dashboard.feed import DashboardFeed
from pendant.ui.dashboard.join_qr import join_urls
from pendant.ui.kit.cell_contact import ContactLog
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.controller_reader import ControllerReader
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.hold_line import HoldLine
from pendant.ui.kit.jobs import PageJobs
from pendant.ui.kit.motion_gate import PROGRAM_RUNNING
from pendant.ui.kit.snapshot import Snapshot, carry_last_known
from pendant.ui.page.activity import ActivityLog, LoggedJogger
from pendant.ui.page.browsers import Browsers, read_handshake
from pendant.ui.page.pacing import RefreshLoop, TickWork
from pendant.ui.page.page_server import serve_page
from pendant.ui.page.program_wiring import open_program_workspace
from pendant.ui.page.roles import ControlDesk
from pendant.ui.page.session import ClientSession
from pendant.ui.page.session_builder import FirstPanel, show_first_panel
from pendant.ui.robot.safety_panel import read_identity
from pendant.ui.scene.arm import ArmScene
from pendant.ui.scene.cell import ObstacleDrawing, ToolShapeDrawing
from pendant.ui.scene.live_cell import LiveCell

log = logging.getLogger(__name__)

__all__ = ["PROGRAM_RUNNING", "PendantUI"]  # PROGRAM_RUNNING: what a refused jog says while a program runs


class PendantUI:
    """Serves the page on `host:port` and keeps every connected browser in step with `controller`.

    `token`: taking control needs it (an exposed pendant); without one, the first browser to connect gets
    control. `events`: the event log, shared with the API server when both run in one process (and kept on
    disk when it has a store). `origins`: the Host and Origin rules for page loads and websockets (None:
    none). `remote`: the Remote control switch shared with the API (by default on: nothing else in this
    process moves the arm). `attempts`: wrong tokens per address, shared with the API's guard. `data_dir`:
    where recordings are kept. `metrics`: counted for GET /metrics. `clock`: the telemetry's time (the
    simulator's own when it runs on a fake clock).
    """

    def __init__(
        self,
        controller: Controller,
        arm: ArmModel,
        *,
        host: str,
        port: int,
        mode_line: str,
        token: str | None = None,
        events: EventLog | None = None,
        programs_dir: str | None = None,
        origins: OriginPolicy | None = None,
        remote: RemoteControl | None = None,
        attempts: FailedAttempts | None = None,
        data_dir: str | None = None,
        metrics: PendantMetrics | None = None,
        clock: Callable[[], float] = time.monotonic,
        cells_folder: str | None = None,
        stops: StopBus | None = None,
        environment_map: EnvironmentMap | None = None,
    ) -> None:
        self.controller = controller
        self.arm = arm
        self.mode_line = mode_line
        self.events = events if events is not None else EventLog()
        # A closing page's stop goes to the jogger made below.
        self.server = serve_page(host, port, origins, self._page_closed_mid_jog)
        self.line = HoldLine(host, origins=origins)  # the operator's holds beside viser's loop and pool
        self.join_urls = join_urls(host, self.server.get_port())  # the QR code people in the room scan
        self.desk = ControlDesk(self.events, token=token, attempts=attempts)
        self.remote = remote if remote is not None else RemoteControl(enabled=True)
        self.remote.holder = lambda: self.desk.name(self.desk.operator)
        self.runner = CommandRunner(controller, gate=self.desk.gate)
        self.activity = ActivityLog(self.events, self.desk, metrics)
        self.runner.on_submit = self.activity.command
        # Stops heard anywhere in this process (the page's, the API's): shared with the API app by the CLI.
        self.stops = stops if stops is not None else StopBus()
        self.loop = RefreshLoop(self.tick)  # woken when a jog starts: its first motion shows at once
        # The controller's cell: its state, and its geometry for the page's checks.
        self.obstacles = ObstacleDrawing(self.server.scene, "/cell")
        self.live_cell = LiveCell(arm, self.obstacles, ContactLog(self.events))
        jog_arm = cast(ArmModel, CellAwareArm(arm, lambda: self.cell_model))  # jogs stop short of obstacles
        self.jogger = LoggedJogger(
            controller,
            jog_arm,
            events=self.events,
            desk=self.desk,
            remote=self.remote,
            on_start=self.loop.wake,
            stops=self.stops,
            touching=lambda q: self.cell_model.touching(q) if self.cell_model is not None else [],
        )
        # Every stop pressed in a page (Freeze, Esc, Protective stop) ends the held jog until it is released.
        self.runner.presser = self.activity.who
        self.runner.on_stop = self.stops.notify
        recordings = recordings_dir(resolve_data_dir(data_dir, programs_dir))  # --data, env, beside programs
        self.telemetry = Telemetry(controller, clock, recordings_folder=recordings, arm=arm_drawing(arm))
        self.events.on_record(self.telemetry.log_event)
        self.programs, self.recovery = open_program_workspace(
            controller,
            arm,
            programs_dir,
            events=self.events,
            desk=self.desk,
            activity=self.activity,
            runner=self.runner,
            latest=lambda: self.latest,
            cell=lambda: self.cell_model,
        )
        # Every stop heard in this process also ends a running program, whatever its step, moving or not.
        self.stops.subscribe(self.programs.runner.stop_heard)
        self.scene = ArmScene(self.server, arm.urdf_path, environment_map=environment_map)
        self.latest = Snapshot(taken_at=0.0)
        self.cells_dir = Path(cells_folder) if cells_folder is not None else cells_dir()
        self.identity = ""  # /robot/info and /version/*, read once the controller answers
        self.tool_shape = ToolShapeDrawing(self.server.scene)
        self.recorder = PathRecorder(recordings)  # "Record path": fed every reading below, kept there
        self.programs.path_recordings = recordings  # a Path step simplified again reads its recording there
        self.browsers = Browsers(hold_back=lambda: self.jogger.pressed)  # the operator's jog first
        self.sessions = self.browsers.sessions  # by client id (tests add theirs under the lock)
        self.dashboard_feed = DashboardFeed(self.telemetry, self.events)
        self.reader = ControllerReader(controller)
        self.desk.on_change(self._control_changed)
        self.remote.on_change(self.browsers.show_remote)
        self.desk.on_ask(lambda asker, operator: self.browsers.tell_asked(operator, self.desk.name(asker)))
        # Arrivals and departures on a thread of their own, handed over from viser's event loop: viser would
        # run them on its callback pool, which any browser's clicks can fill, and a newcomer then waited
        # for its Freeze button for good.
        self._arrivals = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pendant-arrivals")
        self.server.on_client_connect(self._on_connect)
        self.server.on_client_disconnect(self._on_disconnect)
        self.jobs = PageJobs(is_operator=lambda client: self.desk.gate(client) is None)
        if metrics is not None:
            metrics.viewers.set_function(lambda: len(self.browsers.all()))

    def open_session(
        self,
        target: GuiTarget,
        *,
        client_id: int | None = None,
        url_token: str | None = None,
        freeze: viser.GuiButtonHandle | None = None,
    ) -> ClientSession:
        """Build the panels on `target`: a browser's own GUI, or the server's (headless tests)."""
        return ClientSession(
            target,
            controller=self.controller,
            arm=self.arm,
            runner=self.runner,
            jogger=self.jogger,
            mode_line=self.mode_line,
            current_q=lambda: self.latest.q,
            current_tool=lambda: self.T_flange_tool,
            current_cell=lambda: self.cell_model,
            cell_state=lambda: self.cell_state,
            cells_dir=self.cells_dir,
            recorder=self.recorder,
            recovery=self.recovery,
            desk=self.desk,
            telemetry=self.telemetry,
            events=self.events,
            programs=self.programs,
            client_id=client_id,
            url_token=url_token,
            remote=self.remote,
            join_urls=self.join_urls,
            on_recording=self.activity.recording,
            freeze=freeze,
            jobs=self.jobs,
            line=self.line,
        )

    def start(self) -> PendantUI:
        self.refresh()
        self.refresh_cell()
        self.jogger.start_watchdog()
        self.loop.start()
        return self

    def _page_closed_mid_jog(self) -> None:
        jogger = getattr(self, "jogger", None)  # a request before the jogger exists has nothing to stop
        if jogger is not None and jogger.pressed:
            jogger.release("page closed")

    def stop(self) -> None:
        self.loop.stop()
        self.jogger.stop_watchdog()
        self.runner.shutdown()
        self.jobs.shutdown()
        self._arrivals.shutdown(wait=False, cancel_futures=True)
        self.browsers.builder.stop()
        self.telemetry.stop_recording()  # SIGTERM or Ctrl-C: a running recording's file is finished
        self.server.stop()
        self.line.stop()

    def refresh(self, *, with_io: bool = True, flush: bool = False) -> Snapshot:
        """Read the controller once and show what it says (IO and tool only when `with_io`); `flush` sends
        it at once rather than in viser's next 1/60 s window (the first motion after a jog press)."""
        snapshot = self.reader.read(self.latest, with_io=with_io)
        if snapshot.q is not None:
            T_base_flange = self.arm.fk(snapshot.q)
            opening = snapshot.gripper_opening if snapshot.gripper_opening is not None else 0.0
            self.scene.show(snapshot.q, opening, T_base_flange @ self.T_flange_tool, snapshot.taken_at)
            self.tool_shape.show(self.cell_state.tool_shape, T_base_flange)
        self.recorder.add(snapshot.taken_at, snapshot.q, snapshot.position, snapshot.outputs, snapshot.inputs)
        snapshot = carry_last_known(self.latest, snapshot)  # a fault shows where the arm last was, greyed
        if snapshot.motion_status != self.latest.motion_status and snapshot.online:
            self.refresh_cell()  # the failure behind a new state, read now: the banner says why at once
        runs = self.programs.runner
        self.recovery.update(snapshot, self.cell_state, runs.progress, can_resume=runs.can_resume)
        self.activity.state_changed(self.latest, snapshot)
        self.latest = snapshot
        for session in self.browsers.all():
            session.show(snapshot, with_io=with_io)
        if flush:  # only then: flushing every tick costs the viewers' update rate (benchmarks/viewers.py)
            self.server.flush()
        return snapshot

    @property
    def T_flange_tool(self) -> np.ndarray:
        """The tool's TCP on the flange: the scene's TCP frame and the gizmo."""
        return self.reader.T_flange_tool

    @property
    def cell_state(self) -> CellState:
        return self.live_cell.state

    @property
    def cell_model(self) -> CellModel | None:
        """The controller's cell as geometry, for the page's checks (None before the first read)."""
        return self.live_cell.model

    def refresh_cell(self) -> CellState:
        """Read the controller's cell and safety state; draw the obstacles (red where the arm touches one)
        and tell every browser."""
        changed = self.live_cell.update(self.controller, self.latest.q, self.reader.tool)
        state = self.live_cell.state
        if not self.identity and self.latest.online:
            self.identity = read_identity(self.controller)
        for session in self.browsers.all():
            session.show_cell(state, self.identity, cell_changed=changed)
        return state

    def refresh_dashboard(self, *, sample: bool = True, table: bool = True, plots: bool = True) -> None:
        """Read the motors once for everybody and push the shared renderings to every dashboard."""
        self.dashboard_feed.push(
            self.latest,
            self.browsers.all(),
            sample=sample,
            table=table,
            plots=plots,
            arm=lambda: arm_state(self.latest, self.cell_state, self.programs),
        )

    # --- browsers -----------------------------------------------------------------------------------
    async def _on_connect(self, client: viser.ClientHandle) -> None:
        self._hand_over(self._connect, client)

    async def _on_disconnect(self, client: viser.ClientHandle) -> None:
        self._hand_over(self.disconnect, client)

    def _hand_over(self, work: Callable[[viser.ClientHandle], None], client: viser.ClientHandle) -> None:
        with contextlib.suppress(RuntimeError):  # shut down: the page is closing
            self._arrivals.submit(work, client).add_done_callback(_log_arrival_failure)

    def _connect(self, client: viser.ClientHandle) -> None:
        address, token = read_handshake(self.server, client.client_id)
        self.desk.join(client.client_id, address)  # now: the first browser to connect gets control
        first = show_first_panel(client, self.runner)  # Freeze now; the rest when the builder comes to it
        self.browsers.builder.submit(client.client_id, lambda: self._build_session(client, token, first))

    def _build_session(self, client: viser.ClientHandle, token: str | None, first: FirstPanel) -> None:
        session = self.open_session(client, client_id=client.client_id, url_token=token, freeze=first.freeze)
        first.loading.remove()
        session.show(self.latest, with_io=True)
        session.show_cell(self.cell_state, self.identity, cell_changed=True)
        if not self.browsers.add(client.client_id, session):
            return  # it left while its panels were being built
        session.apply_role(self.desk.operator)  # control may have changed while it was being built
        self.dashboard_feed.show_log_again()  # show the new browser the log at once

    def disconnect(self, client: viser.ClientHandle) -> None:
        """A browser left (viser calls this when its websocket closes)."""
        who = self.desk.name(client.client_id)
        if self.programs.supervisor == client.client_id and self.programs.progress.active:
            # Off viser's thread, on the stop path: the run pauses (the arm held) before anything else.
            self.runner.submit(
                "Pause (the page running the program closed)",
                lambda _: self.programs.supervisor_left(client.client_id, who),
                None,
                urgent=True,
                announce=False,
            )
        self.browsers.remove(client.client_id)
        self.desk.leave(client.client_id)  # the operator leaving releases control (and stops a jog)

    def _control_changed(self, operator: int | None) -> None:
        if self.jogger.pressed:
            self.jogger.release("control changed")  # the operator left or handed over: no jog goes on
        self.browsers.apply_role(operator)

    # --- the loop -----------------------------------------------------------------------------------
    def tick(self, work: TickWork, woken: bool) -> None:
        """One step of the refresh loop: the live view, and the cell and the dashboard when `work` says."""
        try:
            self.refresh(with_io=work.io, flush=woken)
            if work.cell:
                self.refresh_cell()
            if work.sample:
                self.refresh_dashboard(table=work.table, plots=work.plots)
        except Exception:  # a broken browser connection must not stop the live view for the others
            log.exception("refresh failed")


def _log_arrival_failure(done: Future[None]) -> None:
    error = None if done.cancelled() else done.exception()
    if error is not None:
        log.error("a browser's arrival or departure failed", exc_info=error)
