"""Serving the API port with uvicorn so that no client can crowd out PUT /freeze.

uvicorn alone keeps a connection that never sends a request open forever, and one that trickles a byte every
few seconds too (its keep-alive timer restarts on every byte). About 1,000 such connections exhausted the
process's open files (the usual limit is 1,024): every new connection then failed, a stop included
(issue #16). Here, per connection:

- a request must arrive in full (headers and body) within `REQUEST_READ_TIMEOUT_S` of the moment the server
  started waiting for it (connection opened, or previous answer sent), else the connection is closed;
- an idle keep-alive connection is closed after `KEEP_ALIVE_TIMEOUT_S`;
- at most `max_connections` are open: a new one beyond that closes the connection that has waited longest
  for its request (never one whose request is being handled), so a new client, a stop, always gets in.

The open-file limit is raised to its hard limit at start, and `max_connections` kept well below it. The
GIL is handed over more often than Python's default, so a thread planning a motion or parsing a body cannot
keep the event loop (and PUT /freeze) waiting for long.
"""

from __future__ import annotations

import asyncio
import resource
import sys
import time
from typing import Any

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

KEEP_ALIVE_TIMEOUT_S = 5.0
# The largest allowed body (128 KiB) takes well under a second even over a slow link.
REQUEST_READ_TIMEOUT_S = 10.0
MAX_CONNECTIONS = 1000
# Files the rest of the process needs (the UI's websockets, program files, logs, libraries).
RESERVED_FILES = 256
MIN_CONNECTIONS = 64
# How long a thread may hold the GIL while another waits for it (Python's default is 5 ms). A planning or
# parsing thread made the event loop wait that long at every I/O step of a PUT /freeze: p99 50-70 ms with two
# 100-waypoint runs being planned. 1 ms brings it to ~10 ms, at a small cost in the planners' throughput.
GIL_SWITCH_INTERVAL_S = 0.001


def raise_open_file_limit() -> int:
    """Raise the soft limit on open files to the hard one; the soft limit now in force."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if hard == resource.RLIM_INFINITY or soft < hard:
        target = hard if hard != resource.RLIM_INFINITY else max(soft, 65536)
        try:
            resource.setrlimit(resource.RLIMIT_NOFILE, (target, hard))
            soft = target
        except (ValueError, OSError):
            pass  # keep the soft limit: the connection cap below follows it
    return soft


def connection_cap(open_file_limit: int) -> int:
    """How many API connections to keep open at most, leaving files for everything else."""
    return max(MIN_CONNECTIONS, min(MAX_CONNECTIONS, open_file_limit - RESERVED_FILES))


class GuardedHttpProtocol(HttpToolsProtocol):
    """uvicorn's httptools protocol with a request read deadline and a connection cap (see the module)."""

    max_connections = MAX_CONNECTIONS
    request_read_timeout_s = REQUEST_READ_TIMEOUT_S

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._read_deadline: asyncio.TimerHandle | None = None
        self.waiting_since: float | None = None  # None while a request is being handled

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]
        super().connection_made(transport)
        self._start_waiting()
        if len(self.connections) > self.max_connections:
            self._close_longest_waiting()

    def connection_lost(self, exc: Exception | None) -> None:
        self._stop_waiting()
        super().connection_lost(exc)

    def on_message_complete(self) -> None:
        self._stop_waiting()  # the request is in: what follows is the app's time, not the client's
        super().on_message_complete()

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if not self.transport.is_closing() and not self.pipeline:
            self._start_waiting()

    def _start_waiting(self) -> None:
        self._stop_waiting()
        self.waiting_since = time.monotonic()
        self._read_deadline = self.loop.call_later(self.request_read_timeout_s, self._read_timed_out)

    def _stop_waiting(self) -> None:
        self.waiting_since = None
        if self._read_deadline is not None:
            self._read_deadline.cancel()
            self._read_deadline = None

    def _read_timed_out(self) -> None:
        self._read_deadline = None
        if not self.transport.is_closing():
            self.transport.close()

    def _close_longest_waiting(self) -> None:
        waiting = [
            c
            for c in self.connections
            if c is not self and isinstance(c, GuardedHttpProtocol) and c.waiting_since is not None
        ]
        if waiting:
            oldest = min(waiting, key=lambda c: c.waiting_since or 0.0)
            oldest._stop_waiting()
            oldest.transport.close()


def guarded_protocol(
    max_connections: int, request_read_timeout_s: float = REQUEST_READ_TIMEOUT_S
) -> type[GuardedHttpProtocol]:
    """The protocol class to give uvicorn (`http=`): at most `max_connections`, each request read in
    `request_read_timeout_s`."""
    settings = {"max_connections": max_connections, "request_read_timeout_s": request_read_timeout_s}
    return type("GuardedHttpProtocol", (GuardedHttpProtocol,), settings)


def serve(app: Any, host: str, port: int) -> None:
    """Serve `app` with uvicorn until interrupted (blocks), guarded as described above."""
    import uvicorn

    sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
    uvicorn.run(
        app,
        host=host,
        port=port,
        http=guarded_protocol(connection_cap(raise_open_file_limit())),
        timeout_keep_alive=int(KEEP_ALIVE_TIMEOUT_S),
        access_log=False,  # a log line per request would cost more than the request itself
        log_level="warning",
    )
