"""The pendant's web UI: one shared 3D scene, and for every browser its own panels (see session.py)."""

from __future__ import annotations

import logging
import threading
import time
from dataclasses import replace

import viser

from pendant.controller import Controller, ControllerError
from pendant.jog import Jogger
from pendant.kinematics import ArmModel
from pendant.ui.commands import CommandRunner
from pendant.ui.gui_target import GuiTarget
from pendant.ui.scene import ArmScene
from pendant.ui.session import ClientSession
from pendant.ui.snapshot import Snapshot, read_snapshot

log = logging.getLogger(__name__)

REFRESH_HZ = 30.0
IO_EVERY_N_TICKS = 6  # IO and tool change rarely: read them at 5 Hz


class PendantUI:
    """Serves the page on `host:port` and keeps every connected browser in step with `controller`."""

    def __init__(self, controller: Controller, arm: ArmModel, *, host: str, port: int, mode_line: str) -> None:
        self.controller = controller
        self.arm = arm
        self.mode_line = mode_line
        self.server = viser.ViserServer(host=host, port=port, label="PULSE pendant", verbose=False)
        self.server.gui.configure_theme(control_width="large", show_logo=False)
        self.runner = CommandRunner(controller)
        self.jogger = Jogger(controller, arm)
        self.scene = ArmScene(self.server, arm.urdf_path)
        self.latest = Snapshot(taken_at=0.0)
        self.sessions: dict[int, ClientSession] = {}
        self._sessions_lock = threading.Lock()
        self._robot_id = self._read_quietly(controller.get_robot_id, "")
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._refresh_loop, name="pendant-refresh", daemon=True)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    def open_session(self, target: GuiTarget) -> ClientSession:
        """Build the panels on `target`: a browser's own GUI, or the server's (headless tests)."""
        return ClientSession(
            target,
            controller=self.controller,
            arm=self.arm,
            runner=self.runner,
            jogger=self.jogger,
            mode_line=self.mode_line,
            current_q=lambda: self.latest.q,
        )

    def start(self) -> PendantUI:
        self.refresh()
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
        with self._sessions_lock:
            sessions = list(self.sessions.values())
        for session in sessions:
            session.show(snapshot, with_io=with_io)
        return snapshot

    def _connect(self, client: viser.ClientHandle) -> None:
        session = self.open_session(client)
        session.show(self.latest, with_io=True)
        with self._sessions_lock:
            self.sessions[client.client_id] = session

    def _disconnect(self, client: viser.ClientHandle) -> None:
        with self._sessions_lock:
            self.sessions.pop(client.client_id, None)

    def _refresh_loop(self) -> None:
        period = 1.0 / REFRESH_HZ
        tick = 0
        next_at = time.monotonic()
        while not self._stop.is_set():
            try:
                self.refresh(with_io=tick % IO_EVERY_N_TICKS == 0)
            except Exception:  # a broken browser connection must not stop the live view for the others
                log.exception("refresh failed")
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
