"""Quitting stops the arm: a pendant that drives an arm sends it a Freeze before it stops serving.

SIGTERM, SIGINT (Ctrl+C) and a normal shutdown all go through uvicorn's shutdown; `QuitAwareServer` starts
the Freeze the moment the signal arrives (in a thread of its own: the signal may have interrupted code
holding the controller's lock) and waits for it, bounded, before the server winds down. The Freeze is
logged in the event log and on stderr. `kill -9` (SIGKILL) ends the process at once: nothing can run then,
so the arm keeps doing what it was told (a motion already sent runs to its end): wire a hardware stop.
"""

from __future__ import annotations

import asyncio
import signal
import socket
import sys
import threading
from collections.abc import Callable
from types import FrameType

import uvicorn

from pendant.eventlog import EventKind, EventLog

# Longer than any controller's connect + read timeout: the Freeze has time to arrive or to fail.
QUIT_FREEZE_WAIT_S = 10.0
QUIT_SOURCE = "pendant"

QuitHook = Callable[[str], None]
"""Called once when the pendant quits, with why ("SIGTERM", "SIGINT", "shutdown")."""


def freeze_on_quit(freeze: Callable[[], None], events: EventLog | None = None) -> QuitHook:
    """A QuitHook that freezes the arm with `freeze` and says so (event log and stderr), failure included."""

    def quit_freeze(reason: str) -> None:
        try:
            freeze()
        except Exception as error:  # an unreachable controller: say so, and quit anyway
            line = f"Quitting ({reason}): PUT /freeze failed: {error}"
            kind = EventKind.ERROR
        else:
            line = f"Quitting ({reason}): PUT /freeze sent, the arm is frozen"
            kind = EventKind.COMMAND
        if events is not None:
            events.record(kind, QUIT_SOURCE, line)
        print(f"pendant: {line}", file=sys.stderr, flush=True)

    return quit_freeze


class QuitAwareServer(uvicorn.Server):
    """uvicorn's server, calling `on_quit` once, first thing, when it is told to quit (signal or shutdown)."""

    def __init__(self, config: uvicorn.Config, on_quit: QuitHook | None = None) -> None:
        super().__init__(config)
        self.on_quit = on_quit
        self._quitting: threading.Thread | None = None
        self._quit_lock = threading.Lock()

    def begin_quit(self, reason: str) -> None:
        """Start `on_quit(reason)` in its own thread, unless it has started already."""
        if self.on_quit is None:
            return
        with self._quit_lock:
            if self._quitting is not None:
                return
            self._quitting = threading.Thread(
                target=self.on_quit, args=(reason,), name="pendant-quit-freeze", daemon=True
            )
            self._quitting.start()

    def handle_exit(self, sig: int, frame: FrameType | None) -> None:
        self.begin_quit(signal.Signals(sig).name)
        super().handle_exit(sig, frame)

    async def shutdown(self, sockets: list[socket.socket] | None = None) -> None:
        self.begin_quit("shutdown")
        if self._quitting is not None:
            await asyncio.to_thread(self._quitting.join, QUIT_FREEZE_WAIT_S)
        await super().shutdown(sockets)
