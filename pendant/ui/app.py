"""The pendant's web UI: one shared 3D scene, and for every browser its own panels (see session.py).

Many browsers may watch; one of them is the operator (roles.py). The refresh loop reads the controller for
everybody: the state at 30 Hz, the motors at 10 Hz into one shared history (the dashboard), and logs state
changes and errors to the event log.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import cast
from urllib.parse import parse_qs, urlsplit

import numpy as np
import viser

from pendant.access import TOKEN_QUERY
from pendant.access.origin import OriginPolicy
from pendant.access.remote import RemoteControl
from pendant.access.throttle import FailedAttempts
from pendant.cell.file import cells_dir
from pendant.cell.geometry import CellAwareArm, CellModel
from pendant.controller import Controller, ControllerError, MotionStatus, Tool
from pendant.controller.stops import StopBus
from pendant.eventlog import EventKind, EventLog
from pendant.eventquery import EventQuery
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import position_to_matrix
from pendant.monitoring import PendantMetrics
from pendant.monitoring import data_dir as resolve_data_dir
from pendant.program import ProgramWorkspace
from pendant.program.runner import RunState
from pendant.teach.recording import PathRecorder
from pendant.telemetry import Telemetry, arm_drawing, recordings_dir
from pendant.ui.dashboard.arm_state import arm_state
from pendant.ui.dashboard.events import render_events
from pendant.ui.dashboard.join_qr import join_urls
from pendant.ui.dashboard.panel import render_motor_table
from pendant.ui.dashboard.plots import PlotData, plot_data
from pendant.ui.kit.cell_state import CellState, read_cell_state
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.snapshot import Snapshot, read_snapshot
from pendant.ui.page.activity import ActivityLog, LoggedJogger
from pendant.ui.page.client_page import page_first
from pendant.ui.page.roles import ControlDesk
from pendant.ui.page.session import ClientSession
from pendant.ui.page.ws_guard import guarded_viser_server
from pendant.ui.robot.safety_panel import read_identity
from pendant.ui.scene.arm import ArmScene
from pendant.ui.scene.cell import ObstacleDrawing, ToolShapeDrawing

log = logging.getLogger(__name__)

REFRESH_HZ = 30.0
IO_EVERY_N_TICKS = 6  # IO and tool change rarely: read them at 5 Hz
MOTORS_EVERY_N_TICKS = 3  # motors at 10 Hz into the shared history
TABLE_EVERY_N_TICKS = 6  # the motor table and the event log redrawn at 5 Hz
PLOTS_EVERY_N_TICKS = 15  # the plots at 2 Hz (at most MAX_POINTS a series)
PROGRAM_RUNNING = "A program is running: Pause or Stop it first"
CELL_EVERY_N_TICKS = 10  # the cell, system state and failures at 3 Hz (a script may change the cell)


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
    ) -> None:
        self.controller = controller
        self.arm = arm
        self.mode_line = mode_line
        self.events = events if events is not None else EventLog()
        # The pendant's page, behind the guard; a closing page's stop goes to the jogger made below.
        with guarded_viser_server(origins, wrap=lambda inner: page_first(inner, self._page_closed_mid_jog)):
            self.server = viser.ViserServer(host=host, port=port, label="PULSE pendant", verbose=False)
        self.server.gui.configure_theme(control_width="large", show_logo=False)
        # Docked, not floating over the view: the arm stays in sight on a portrait tablet, and software WebGL
        # draws no pixels the panel would cover.
        self.server.gui.main_panel.dock_right()
        self.join_urls = join_urls(host, self.server.get_port())  # the QR code people in the room scan
        self.desk = ControlDesk(self.events, token=token, attempts=attempts)
        self.remote = remote if remote is not None else RemoteControl(enabled=True)
        self.remote.holder = lambda: self.desk.name(self.desk.operator)
        self.runner = CommandRunner(controller, gate=self.desk.gate)
        self.activity = ActivityLog(self.events, self.desk, metrics)
        self.runner.on_submit = self.activity.command
        self._stop = threading.Event()
        # Stops heard anywhere in this process (the page's, the API's): shared with the API app by the CLI.
        self.stops = stops if stops is not None else StopBus()
        self._wake = threading.Event()  # a jog started: show its first motion now, not at the next tick
        self.cell_model: CellModel | None = None  # the controller's cell as geometry, for the page's checks
        jog_arm = cast(ArmModel, CellAwareArm(arm, lambda: self.cell_model))  # jogs stop short of obstacles
        self.jogger = LoggedJogger(
            controller,
            jog_arm,
            events=self.events,
            desk=self.desk,
            remote=self.remote,
            on_start=self._wake.set,
            stops=self.stops,
            touching=lambda q: self.cell_model.touching(q) if self.cell_model is not None else [],
        )
        # Every stop pressed in a page (Freeze, Esc, Protective stop) ends the held jog until it is released.
        self.runner.on_stop = lambda label, client: self.stops.notify(
            f"{label} by {self.activity.who(client)}"
        )
        recordings = recordings_dir(resolve_data_dir(data_dir, programs_dir))  # --data, env, beside programs
        self.telemetry = Telemetry(controller, clock, recordings_folder=recordings, arm=arm_drawing(arm))
        self.events.on_record(self.telemetry.log_event)
        self.programs = ProgramWorkspace.for_controller(controller, programs_dir)
        # Each version's author: the operator's browser (only the operator may save).
        self.programs.versions.who = lambda: self.desk.name(self.desk.operator)
        self.programs.on_change(lambda change: self.activity.program_changed(self.programs, change))
        self.runner.motion_block = self._motion_block
        self.runner.explain = self._explain
        if self.programs.store.restore_problem is not None:
            self.events.record(EventKind.ERROR, "program", self.programs.store.restore_problem)
        self.scene = ArmScene(self.server, arm.urdf_path)
        self.latest = Snapshot(taken_at=0.0)
        self.T_flange_tool = np.eye(4)  # the tool's TCP on the flange: the scene's TCP frame and the gizmo
        self.cells_dir = Path(cells_folder) if cells_folder is not None else cells_dir()
        self.cell_state = CellState()
        self.identity = ""  # /robot/info and /version/*, read once the controller answers
        self.obstacles = ObstacleDrawing(self.server.scene, "/cell")
        self.tool_shape = ToolShapeDrawing(self.server.scene)
        self.recorder = PathRecorder(recordings)  # "Record path": fed every reading below, kept there
        self.programs.path_recordings = recordings  # a Path step simplified again reads its recording there
        self._tool: Tool | None = None
        self.cell_model_tool: Tool | None = None
        self.sessions: dict[int, ClientSession] = {}
        self._sessions_lock = threading.Lock()
        self._gone: set[int] = set()  # clients that left before their session was built
        self._robot_id = self._read_quietly(controller.get_robot_id, "")
        self._events_seq = -1
        self._thread = threading.Thread(target=self._refresh_loop, name="pendant-refresh", daemon=True)
        self.desk.on_change(self._control_changed)
        self.remote.on_change(self._remote_changed)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)
        if metrics is not None:
            metrics.viewers.set_function(lambda: len(self._sessions()))

    def open_session(
        self, target: GuiTarget, *, client_id: int | None = None, url_token: str | None = None
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
            desk=self.desk,
            telemetry=self.telemetry,
            events=self.events,
            programs=self.programs,
            client_id=client_id,
            url_token=url_token,
            remote=self.remote,
            join_urls=self.join_urls,
            on_recording=lambda client, message: self.events.record(
                EventKind.COMMAND, self.activity.who(client), message
            ),
        )

    def start(self) -> PendantUI:
        self.refresh()
        self.refresh_cell()
        self.jogger.start_watchdog()
        self._thread.start()
        return self

    def _page_closed_mid_jog(self) -> None:
        jogger = getattr(self, "jogger", None)  # a request before the jogger exists has nothing to stop
        if jogger is not None and jogger.pressed:
            jogger.release("page closed")

    def stop(self) -> None:
        self._stop.set()
        self._wake.set()
        if self._thread.is_alive():
            self._thread.join(timeout=2.0)
        self.jogger.stop_watchdog()
        self.runner.shutdown()
        self.telemetry.stop_recording()  # SIGTERM or Ctrl-C: a running recording's file is finished
        self.server.stop()

    def refresh(self, *, with_io: bool = True, flush: bool = False) -> Snapshot:
        """Read the controller once and show what it says (IO and tool only when `with_io`); `flush` sends
        it at once rather than in viser's next 1/60 s window (the first motion after a jog press)."""
        snapshot = read_snapshot(
            self.controller, with_io=with_io, robot_id=self._robot_id, tool_name=self.latest.tool_name
        )
        if not with_io:
            snapshot = replace(snapshot, outputs=self.latest.outputs, inputs=self.latest.inputs)
        elif snapshot.online:  # an offline controller would only make each of these reads time out too
            tool = self._read_quietly(self.controller.get_tool, None)
            if tool is not None:
                self.T_flange_tool = position_to_matrix(tool.position)
                self._tool = tool
                snapshot = replace(snapshot, tool_name=tool.name)
            if not self._robot_id:  # the controller was unreachable when the pendant started
                self._robot_id = self._read_quietly(self.controller.get_robot_id, "")
                snapshot = replace(snapshot, robot_id=self._robot_id)
        if snapshot.q is not None:
            T_base_tcp = self.arm.fk(snapshot.q) @ self.T_flange_tool
            opening = snapshot.gripper_opening if snapshot.gripper_opening is not None else 0.0
            self.scene.show(snapshot.q, opening, T_base_tcp, snapshot.taken_at)
            self.tool_shape.show(self.cell_state.tool_shape, self.arm.fk(snapshot.q))
        self.recorder.add(snapshot.taken_at, snapshot.q, snapshot.position, snapshot.outputs, snapshot.inputs)
        self.activity.state_changed(self.latest, snapshot)
        self.latest = snapshot
        for session in self._sessions():
            session.show(snapshot, with_io=with_io)
        if flush:  # only then: flushing every tick costs the viewers' update rate (benchmarks/viewers.py)
            self.server.flush()
        return snapshot

    def refresh_cell(self) -> CellState:
        """Read the controller's cell and safety state; draw the obstacles (red where the arm touches one)
        and tell every browser."""
        previous = self.cell_state
        state = read_cell_state(self.controller, previous)
        changed = (
            self.cell_model is None
            or state.obstacles != previous.obstacles
            or state.tool_shape != previous.tool_shape
            or self._tool is not self.cell_model_tool
        )
        if changed:
            self.cell_model_tool = self._tool
            self.cell_model = CellModel(self.arm, state.obstacles, state.tool_shape, self._tool)
        self.cell_state = state
        q = self.latest.q
        touching = self.cell_model.touching(q) if q is not None and self.cell_model is not None else []
        self.obstacles.show(state.obstacles, touching)
        if not self.identity and self.latest.online:
            self.identity = read_identity(self.controller)
        for session in self._sessions():
            session.show_cell(state, self.identity, cell_changed=changed)
        return state

    def refresh_dashboard(self, *, sample: bool = True, table: bool = True, plots: bool = True) -> None:
        """Read the motors once for everybody and push the shared renderings to every dashboard."""
        if sample:
            self.telemetry.sample(arm_state(self.latest, self.cell_state, self.programs))
        table_html = render_motor_table(self.telemetry.latest) if table else None
        plot_cache: dict[float, PlotData] = {}  # one per window length the browsers show

        def plots_for(window_s: float) -> PlotData:
            if window_s not in plot_cache:
                plot_cache[window_s] = plot_data(self.telemetry.window(window_s), window_s)
            return plot_cache[window_s]

        events_cache: dict[EventQuery, str] = {}  # one search per distinct filter

        def events_for(query: EventQuery) -> str:
            if query not in events_cache:
                events_cache[query] = render_events(self.events.search(query))
            return events_cache[query]

        show_events = table and self.events.searchable_seq != self._events_seq
        if show_events:
            self._events_seq = self.events.searchable_seq
        for session in self._sessions():
            session.show_dashboard(
                table_html=table_html,
                plots=plots_for if plots else None,
                events=events_for if show_events else None,
            )

    # --- browsers -----------------------------------------------------------------------------------
    def _connect(self, client: viser.ClientHandle) -> None:
        address, url_token = self._handshake(client)
        self.desk.join(client.client_id, address)
        session = self.open_session(client, client_id=client.client_id, url_token=url_token)
        session.show(self.latest, with_io=True)
        session.show_cell(self.cell_state, self.identity, cell_changed=True)
        with self._sessions_lock:
            if client.client_id in self._gone:  # it left while its panels were being built
                self._gone.discard(client.client_id)
                session.close()
                return
            self.sessions[client.client_id] = session
        session.apply_role(self.desk.operator)  # control may have changed while it was being built
        self._events_seq = -1  # show the new browser the log at once

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._sessions_lock:
            session = self.sessions.pop(client.client_id, None)
            if session is None:
                self._gone.add(client.client_id)
        if session is not None:
            session.close()
        self.desk.leave(client.client_id)  # the operator leaving releases control (and stops a jog)

    def _handshake(self, client: viser.ClientHandle) -> tuple[str | None, str | None]:
        """The browser's address and the token its page URL carried into the websocket URL (`?token=`).

        viser 1.1.1 keeps each websocket connection (with its opening handshake) in its server's
        `_live_connections`; not public API, so anything unexpected means "no token from the URL" and the
        "Access token" field remains the way in.
        """
        try:
            connection = self.server._websock_server._live_connections.get(client.client_id)
            if connection is None:
                return None, None
            remote = connection.remote_address
            address = str(remote[0]) if remote else None
            if connection.request is None:
                return address, None
            query = parse_qs(urlsplit(connection.request.path).query)
            tokens = query.get(TOKEN_QUERY)
            return address, tokens[0] if tokens else None
        except Exception:  # private API of viser: never let it break a connection
            log.debug("could not read the websocket handshake", exc_info=True)
            return None, None

    def _control_changed(self, operator: int | None) -> None:
        if self.jogger.pressed:
            self.jogger.release("control changed")  # the operator left or handed over: no jog goes on
        for session in self._sessions():
            session.apply_role(operator)

    def _remote_changed(self, enabled: bool) -> None:
        for session in self._sessions():
            session.control.show_remote(enabled)

    def _sessions(self) -> list[ClientSession]:
        with self._sessions_lock:
            return list(self.sessions.values())

    # --- the loop -----------------------------------------------------------------------------------
    def _refresh_loop(self) -> None:
        period = 1.0 / REFRESH_HZ
        tick = 0
        next_at = time.monotonic()
        woken = False
        while not self._stop.is_set():
            try:
                self.refresh(with_io=tick % IO_EVERY_N_TICKS == 0, flush=woken)
                if tick % CELL_EVERY_N_TICKS == 2:
                    self.refresh_cell()
                if tick % MOTORS_EVERY_N_TICKS == 1:  # offset: not on the same tick as the IO read
                    self.refresh_dashboard(
                        table=tick % TABLE_EVERY_N_TICKS == 1, plots=tick % PLOTS_EVERY_N_TICKS == 1
                    )
            except Exception:  # a broken browser connection must not stop the live view for the others
                log.exception("refresh failed")
            tick += 1
            next_at += period
            woken = self._wake.wait(max(0.0, next_at - time.monotonic()))
            if woken:
                self._wake.clear()
                next_at = time.monotonic()  # the ticks go on from now
            next_at = max(next_at, time.monotonic() - period)  # after a stall, do not race to catch up

    def _motion_block(self) -> str | None:
        """The page moves the arm only when no program does (Freeze, Pause and Stop always work)."""
        if self.programs.progress.state is RunState.RUNNING:
            return PROGRAM_RUNNING
        return None

    def _explain(self, message: str) -> str:
        """A refused motion in ERROR says so: the controller's own words ("Robot does not respond") name
        no cause."""
        state = self.latest.motion_status
        if state in (MotionStatus.ERROR, MotionStatus.MOTION_FAILED):
            return (
                f"The arm is in {state.value}: press Recover under the status first (controller: {message})"
            )
        return message

    @staticmethod
    def _read_quietly(read, default):  # type: ignore[no-untyped-def]
        try:
            return read()
        except ControllerError:
            return default
