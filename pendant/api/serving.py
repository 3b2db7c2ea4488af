"""Serving the API port with uvicorn so that no client can crowd out PUT /freeze.

uvicorn alone keeps a connection that never sends a request open forever, and one that trickles a byte every
few seconds too (its keep-alive timer restarts on every byte). About 1,000 such connections exhausted the
process's open files (the usual limit is 1,024): every new connection then failed, a stop included
(issue #16). Here, per connection:

- a request must arrive in full (headers and body) within `REQUEST_READ_TIMEOUT_S` of the moment the server
  started waiting for it (connection opened, or previous answer sent), else the connection is closed;
- an idle keep-alive connection is closed after `KEEP_ALIVE_TIMEOUT_S`;
- a request head (request line and headers) is at most `MAX_HEAD_BYTES` (uvicorn's httptools protocol has no
  limit of its own): beyond, 431 and the connection closed;
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
from typing import Any, ClassVar

from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol

from pendant.api.quitting import QuitAwareServer, QuitHook
from pendant.api.wire import text_literal

KEEP_ALIVE_TIMEOUT_S = 5.0
# The largest allowed body (128 KiB) takes well under a second even over a slow link.
REQUEST_READ_TIMEOUT_S = 10.0
MAX_CONNECTIONS = 1000
MAX_HEAD_BYTES = 64 * 1024
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
    # The connections waiting for a request, longest-waiting first (a dict keeps insertion order): evicting
    # one is O(1), however many there are. One per server: guarded_protocol() gives each class its own.
    waiting: ClassVar[dict[GuardedHttpProtocol, None]] = {}

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._read_deadline: asyncio.TimerHandle | None = None
        self._head_bytes = 0  # received since the server started waiting, until the head is complete
        self._reading_head = True

    def connection_made(self, transport: asyncio.Transport) -> None:  # type: ignore[override]  # as uvicorn narrows it
        super().connection_made(transport)
        self._start_waiting()
        if len(self.connections) > self.max_connections:
            self._close_longest_waiting()

    def connection_lost(self, exc: Exception | None) -> None:
        self._stop_waiting()
        super().connection_lost(exc)

    def data_received(self, data: bytes) -> None:
        super().data_received(data)
        if self._reading_head:
            self._head_bytes += len(data)
            if self._head_bytes > MAX_HEAD_BYTES and not self.transport.is_closing():
                self._refuse_head()

    def on_headers_complete(self) -> None:
        self._reading_head = False
        super().on_headers_complete()

    def _refuse_head(self) -> None:
        body = text_literal(f"Request head too large: at most {MAX_HEAD_BYTES} bytes")
        self.transport.write(
            b"HTTP/1.1 431 Request Header Fields Too Large\r\ncontent-type: text/plain; charset=utf-8\r\n"
            b"connection: close\r\ncontent-length: %d\r\n\r\n%s" % (len(body), body)
        )
        self.transport.close()

    def on_message_complete(self) -> None:
        self._stop_waiting()  # the request is in: what follows is the app's time, not the client's
        super().on_message_complete()

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if not self.transport.is_closing() and not self.pipeline:
            self._start_waiting()

    def _start_waiting(self) -> None:
        self._stop_waiting()
        self._head_bytes, self._reading_head = 0, True
        self.waiting[self] = None
        self._read_deadline = self.loop.call_later(self.request_read_timeout_s, self._read_timed_out)

    def _stop_waiting(self) -> None:
        self.waiting.pop(self, None)
        if self._read_deadline is not None:
            self._read_deadline.cancel()
            self._read_deadline = None

    def _read_timed_out(self) -> None:
        self._read_deadline = None
        if not self.transport.is_closing():
            self.transport.close()

    def _close_longest_waiting(self) -> None:
        oldest = next((c for c in self.waiting if c is not self), None)
        if oldest is not None:
            oldest._stop_waiting()
            oldest.transport.close()


def guarded_protocol(
    max_connections: int, request_read_timeout_s: float = REQUEST_READ_TIMEOUT_S
) -> type[GuardedHttpProtocol]:
    """The protocol class to give uvicorn (`http=`): at most `max_connections`, each request read in
    `request_read_timeout_s`."""
    settings = {
        "max_connections": max_connections,
        "request_read_timeout_s": request_read_timeout_s,
        "waiting": {},
    }
    return type("GuardedHttpProtocol", (GuardedHttpProtocol,), settings)


def serve(app: Any, host: str, port: int, on_quit: QuitHook | None = None) -> None:
    """Serve `app` with uvicorn until interrupted (blocks), guarded as described above; `on_quit` is called
    first when it is told to quit (pendant.api.quitting: the arm is frozen)."""
    import uvicorn

    sys.setswitchinterval(GIL_SWITCH_INTERVAL_S)
    config = uvicorn.Config(
        app,
        host=host,
        port=port,
        http=guarded_protocol(connection_cap(raise_open_file_limit())),
        timeout_keep_alive=int(KEEP_ALIVE_TIMEOUT_S),
        access_log=False,  # a log line per request would cost more than the request itself
        log_level="warning",
    )
    QuitAwareServer(config, on_quit).run()
