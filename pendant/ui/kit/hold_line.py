"""The operator's hold-to-run on a line of its own, beside viser's websocket (issue 37).

viser reads every browser's messages on one event loop, the same loop that serialises and sends the
broadcast to every viewer. With 60 viewers of a moving arm that loop ran late by more than the deadman's
200 ms, and the held jog was cut 16-21 times in 30 s although the page sent its confirmations on time.

Here the jog's confirmations ("hold UUID") and its release ("release UUID") come over a websocket of their own
(websockets' threaded server: one thread per connection, no event loop shared with anybody). The connection's
thread confirms the deadman as each message arrives and hands the controller conversation to one worker
thread of its own; a release (the stop out) runs on the connection's thread at once. The deadman's watchdog
already runs on its own thread (pendant.jog.jogger). The page (client_page.js) uses the line when it opens,
for a whole press, and viser's websocket otherwise (a proxy passing one port only): one press never mixes
the two, so a confirmation can never overtake its own release.

A browser learns the line's port and its own key from its jog pad (sent over its own viser websocket, which
the Host, Origin and token rules guard); a connection without a known key is refused.
"""

from __future__ import annotations

import contextlib
import logging
import secrets
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from typing import Protocol
from urllib.parse import parse_qs, urlsplit

from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request, Response
from websockets.sync.server import Server, ServerConnection, serve

from pendant.access.origin import OriginPolicy

log = logging.getLogger(__name__)

MAX_MESSAGE_BYTES = 256  # "release" and a uuid: nothing longer is ever sent
HOLD = "hold"
RELEASE = "release"


class Holder(Protocol):
    """A browser's jog pad: `held(uuid)` on each confirmation, `let_go(uuid)` on its release."""

    def held(self, uuid: str) -> None: ...

    def let_go(self, uuid: str) -> None: ...


class HoldLine:
    """Listens on `host`, on a port of its own (`port`: 0 for any free one)."""

    def __init__(self, host: str, port: int = 0, origins: OriginPolicy | None = None) -> None:
        self._origins = origins
        self._holders: dict[str, Holder] = {}
        self._lock = threading.Lock()
        self._work = ThreadPoolExecutor(max_workers=1, thread_name_prefix="pendant-hold-work")
        self._server: Server = serve(
            self._serve,
            host,
            port,
            process_request=self._check,
            compression=None,  # a few bytes a message: nothing to gain, and the CPU is the operator's
            max_size=MAX_MESSAGE_BYTES,
            ping_interval=1.0,
            ping_timeout=3.0,
        )
        self.port: int = self._server.socket.getsockname()[1]
        self._thread = threading.Thread(
            target=self._server.serve_forever, name="pendant-hold-line", daemon=True
        )
        self._thread.start()

    def register(self, holder: Holder) -> str:
        """A new key for `holder`'s browser (to be sent in its jog pad)."""
        key = secrets.token_urlsafe(18)
        with self._lock:
            self._holders[key] = holder
        return key

    def forget(self, key: str) -> None:
        with self._lock:
            self._holders.pop(key, None)

    def work(self, job: Callable[[], object]) -> None:
        """Talk to the controller off the connection's thread (one job at a time, in order)."""
        with contextlib.suppress(RuntimeError):  # shut down
            self._work.submit(job).add_done_callback(_log_failure)

    def stop(self) -> None:
        self._server.shutdown()
        self._work.shutdown(wait=False, cancel_futures=True)

    def _holder(self, path: str) -> Holder | None:
        keys = parse_qs(urlsplit(path).query).get("key", [])
        with self._lock:
            return self._holders.get(keys[0]) if len(keys) == 1 else None

    def _check(self, connection: ServerConnection, request: Request) -> Response | None:
        if self._origins is not None:
            refusal = self._origins.host_refusal(request.headers.get("Host"))
            if refusal is not None:
                return connection.respond(refusal[0], refusal[1] + "\n")
        if self._holder(request.path) is None:
            return connection.respond(403, "Unknown or expired jog key: reload the page.\n")
        return None

    def _serve(self, connection: ServerConnection) -> None:
        assert connection.request is not None
        path = connection.request.path
        try:
            for message in connection:
                holder = self._holder(path)  # forgotten when its browser left
                if holder is None:
                    connection.close(1008, "jog key expired")
                    return
                verb, _, uuid = str(message).partition(" ")
                if verb == HOLD:
                    holder.held(uuid)
                elif verb == RELEASE:
                    holder.let_go(uuid)
        except ConnectionClosed:
            pass
        except Exception:  # one browser's bad message must not end the line for others
            log.exception("hold line: a message failed")


def _log_failure(future: Future[object]) -> None:
    error = None if future.cancelled() else future.exception()
    if error is not None:
        log.error("hold line: a jog's controller work failed", exc_info=error)
