"""A simulator serving the PULSE API from a thread of this process, on a free loopback port.

What the pytest plugin (`pendant.testing`) starts once per session (per xdist worker) and resets between
tests, and what its benchmark measures: real HTTP, no subprocess, nothing left behind after `stop()`.
The simulator runs on a `ScaledClock` (the time scale) with a `Script` (scripted events).
"""

from __future__ import annotations

import socket
import threading
import time
from collections.abc import Callable

import uvicorn
from starlette.concurrency import run_in_threadpool
from starlette.types import ASGIApp, Receive, Scope, Send

from pendant.api import create_app
from pendant.api.availability import NOT_THE_CONTROLLERS
from pendant.api.quitting import QuitAwareServer, freeze_on_quit
from pendant.sim.clock import ScaledClock, paused
from pendant.sim.script import Script, ScriptedSim

LOOPBACK = "127.0.0.1"
START_TIMEOUT_S = 30.0
STOP_TIMEOUT_S = 10.0
COMMAND_METHODS = frozenset({"PUT", "POST", "DELETE", "PATCH"})


class CommandCounter:
    """ASGI wrapper: counts the commands sent to the PULSE API and fires the events due on each, before
    the command is handled (so a fault scripted on the N-th command is what that command meets).

    Simulated time stands still while a command is handled (parsing, checks, planning): at a high time
    scale the server's own work would otherwise show as delays between the commands of a program.
    `on_request` is told of every request first (the start of a test's time)."""

    def __init__(
        self, app: ASGIApp, script: Script, clock: ScaledClock, on_request: Callable[[], None]
    ) -> None:
        self.app = app
        self.script = script
        self.clock = clock
        self.on_request = on_request

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] == "http":
            self.on_request()
        if (
            scope["type"] != "http"
            or scope["method"] not in COMMAND_METHODS
            or scope["path"].startswith(NOT_THE_CONTROLLERS)
        ):
            await self.app(scope, receive, send)
            return
        with paused(self.clock):
            for event in self.script.command_received():
                # Off the event loop: an action may itself call this server.
                await run_in_threadpool(self.script.fire, event)
            await self.app(scope, receive, send)


class SimServer:
    """`with SimServer(model, time_scale) as server: ... server.url ...`"""

    def __init__(self, model: str = "pulse75", time_scale: float = 1.0) -> None:
        self.model = model
        self.clock = ScaledClock(time_scale)
        self.sim = ScriptedSim(model=model, clock=self.clock)
        self.script = Script(self.sim, self.clock)
        self.sim.attach(self.script)
        self.app = create_app(self.sim)
        self._socket = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self._socket.bind((LOOPBACK, 0))  # the OS picks a free port; it is ours until stop()
        self.port: int = self._socket.getsockname()[1]
        self.url = f"http://{LOOPBACK}:{self.port}"
        counted = CommandCounter(self.app, self.script, self.clock, self.begin)
        config = uvicorn.Config(counted, log_level="warning", access_log=False, lifespan="off")
        self._server = QuitAwareServer(config, freeze_on_quit(self.sim.freeze))  # stopping freezes the arm
        self._origin_hold: float | None = None
        self._thread = threading.Thread(
            target=self._server.run, kwargs={"sockets": [self._socket]}, name="pendant-sim-api", daemon=True
        )

    def start(self) -> SimServer:
        self._thread.start()
        deadline = time.monotonic() + START_TIMEOUT_S
        while not self._server.started:
            if not self._thread.is_alive() or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"the simulator's API did not start on {self.url}")
            time.sleep(0.001)  # uvicorn says "started" by a flag: nothing to wait on
        return self

    def reset(self, time_scale: float) -> None:
        """Power-on state, no scripted event, at `time_scale`; simulated time stands still at the new origin
        until `begin()` (or the first request), so the set-up of a test takes none of it."""
        self.script.reset()
        self.clock.set_scale(time_scale)
        self.sim.reset()
        self._origin_hold = self.script.origin = self.clock.hold()

    def begin(self) -> None:
        """Let simulated time run (the test has started, or talks to the simulator)."""
        held, self._origin_hold = self._origin_hold, None
        if held is not None:
            self.clock.remove_stop(held)

    def stop(self) -> None:
        """Stop serving, close the port, end the threads."""
        self._server.should_exit = True
        if self._thread.is_alive():
            self._thread.join(STOP_TIMEOUT_S)
        self._socket.close()
        self.script.close()

    def __enter__(self) -> SimServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()
