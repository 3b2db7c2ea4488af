"""The live view in Foxglove: the Foxglove WebSocket protocol served by Foxglove's SDK, with the channels
and schemas of the recordings (channels.ArmChannels), fed by the same samples at the same rate. The SDK
names the protocol's subprotocol `foxglove.sdk.v1` (`foxglove.websocket.v1` before) and accepts that name
only: Foxglove's app offers it; a client offering the old name alone is refused. Read-only: it advertises
no capability that lets a client publish, set or call anything.

/arm (the links' meshes) and /cell are written when they change; a client that subscribes later gets them
again at its subscription, so Foxglove draws the arm and the cell whenever it connects."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence

import foxglove
from foxglove.websocket import ChannelView, Client, ServerListener, WebSocketServer

from pendant.controller.types import MotorStatus
from pendant.eventlog import Event
from pendant.telemetry.arm_scene import ArmDrawing
from pendant.telemetry.channels import ArmChannels, ArmState

SERVER_NAME = "PULSE pendant"


class _Resend(ServerListener):
    """The SDK's listener: a subscription to /arm or /cell is answered with the current drawing."""

    def __init__(self, live: LiveView) -> None:
        self._live = live

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        self._live.resend(channel.topic)


class LiveView:
    """A Foxglove WebSocket server on `host:port` (0: a free port; `.port` says which); RuntimeError when it
    cannot listen there. `arm` may be given later (`channels.arm`), before the first sample."""

    def __init__(
        self,
        host: str,
        port: int,
        arm: ArmDrawing | None = None,
        wall_now: Callable[[], float] = time.time,
    ) -> None:
        self._context = foxglove.Context()
        self.channels = ArmChannels(self._context, arm)
        self._wall_now = wall_now
        self._lock = threading.Lock()
        self._server: WebSocketServer = foxglove.start_server(
            name=SERVER_NAME,
            host=host,
            port=port,
            capabilities=[],
            context=self._context,
            server_listener=_Resend(self),
        )
        self.host = host
        self.port = self._server.port

    @property
    def url(self) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"ws://{host}:{self.port}"

    def publish(self, motors: Sequence[MotorStatus], state: ArmState) -> None:
        """One sample, stamped with the wall clock (any thread)."""
        with self._lock:
            self.channels.write_state(int(self._wall_now() * 1e9), motors, state)

    def log_event(self, event: Event) -> None:
        with self._lock:
            self.channels.write_event(event)

    def resend(self, topic: str) -> None:
        time_ns = int(self._wall_now() * 1e9)
        with self._lock:
            if topic == "/arm":
                self.channels.write_arm(time_ns)
            elif topic == "/cell" and self.channels.cell_written is not None:
                self.channels.write_cell(time_ns, self.channels.cell_written)

    def stop(self) -> None:
        self._server.stop()
