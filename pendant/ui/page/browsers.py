"""The connected browsers: each one's session by viser client id, and what its websocket handshake said."""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from urllib.parse import parse_qs, urlsplit

import viser

from pendant.access import TOKEN_QUERY
from pendant.ui.page.session import ClientSession
from pendant.ui.page.session_builder import SessionBuilder

log = logging.getLogger(__name__)


class Browsers:
    """The sessions of the connected browsers, built by `builder` (session_builder). A browser may leave
    while its panels wait to be built (they never are) or are being built: its session is then closed as it
    is added, never kept for a client that is gone."""

    def __init__(self, hold_back: Callable[[], bool] = lambda: False) -> None:
        self.builder = SessionBuilder(hold_back=hold_back)  # `hold_back`: builds wait (the operator jogs)
        self.sessions: dict[int, ClientSession] = {}
        self.lock = threading.Lock()
        self._gone: set[int] = set()  # clients that left before their session was built

    def add(self, client_id: int, session: ClientSession) -> bool:
        """Keep `session`; False (and the session closed) when its browser has already left."""
        with self.lock:
            if client_id in self._gone:
                self._gone.discard(client_id)
                session.close()
                return False
            self.sessions[client_id] = session
        return True

    def remove(self, client_id: int) -> None:
        """The browser left: close its session, or remember it left if its session is still being built."""
        if self.builder.cancel(client_id):
            return  # still waiting for its build: it never gets one
        with self.lock:
            session = self.sessions.pop(client_id, None)
            if session is None:
                self._gone.add(client_id)
        if session is not None:
            session.close()

    def all(self) -> list[ClientSession]:
        with self.lock:
            return list(self.sessions.values())

    def apply_role(self, operator: int | None) -> None:
        """Control changed hands: every browser shows its role (operator or viewer)."""
        for session in self.all():
            session.apply_role(operator)

    def tell_asked(self, operator: int, asker_name: str) -> None:
        """The operator's page says who asks for control."""
        with self.lock:
            session = self.sessions.get(operator)
        if session is not None:
            session.control.asked(asker_name)

    def show_remote(self, enabled: bool) -> None:
        for session in self.all():
            session.control.show_remote(enabled)


def read_handshake(server: viser.ViserServer, client_id: int) -> tuple[str | None, str | None]:
    """The browser's address and the token its page URL carried into the websocket URL (`?token=`).

    viser 1.1.1 keeps each websocket connection (with its opening handshake) in its server's
    `_live_connections`; not public API, so anything unexpected means "no token from the URL" and the
    "Access token" field remains the way in.
    """
    try:
        connection = server._websock_server._live_connections.get(client_id)
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
