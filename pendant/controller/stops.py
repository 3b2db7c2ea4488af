"""Word of a stop, for whoever must hold still after it: the jogger latches the held press (pendant.jog).

The page's Freeze and Esc, the API's stop routes (on the simulator and through the proxy) and the deadman
`notify` here, before the stop goes to the controller: a jog confirmation that slips in between then sees
the stop and freezes its own motion again. Listeners run on the caller's thread (the API's event loop
included), so they must be quick and never talk to the controller.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

log = logging.getLogger(__name__)

StopListener = Callable[[str], None]

# Where a pendant's API says how many stops it has heard and the last one's cause (pendant.api.stop_notice
# answers it; `pendant run` polls it).
STOPS_PATH = "/pendant/stops"


class StopBus:
    """Stops heard of, passed on with their cause in the page's words ("Freeze from the API (10.0.0.9)")."""

    def __init__(self) -> None:
        self._listeners: list[StopListener] = []
        self._lock = threading.Lock()
        self.count = 0  # stops heard since start: a client (`pendant run`) that polls it sees every one
        self.last_cause = ""

    def subscribe(self, listener: StopListener) -> None:
        with self._lock:
            self._listeners.append(listener)

    def notify(self, cause: str) -> None:
        """Tell every listener; one that fails is logged and never keeps the stop from the others."""
        with self._lock:
            listeners = list(self._listeners)
            self.count += 1
            self.last_cause = cause
        for listener in listeners:
            try:
                listener(cause)
            except Exception:  # a stop must go through whatever a listener does
                log.exception("stop listener failed on %r", cause)
