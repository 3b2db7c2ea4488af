"""`pendant run` against a pendant's API: a stop sent to that pendant from anywhere (its page's Freeze,
another script's `PUT /freeze`) ends the run too, at its next look, even while the arm stands still in a
wait or a gripper step. The pendant counts the stops it hears (GET /pendant/stops); this polls the count.

A bare controller has no such count: a stop another client sends it while the arm is idle cannot be seen
from here (docs/stops.md says so); a stop during a motion still shows as the arm stopping short.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

import httpx

from pendant.controller.stops import STOPS_PATH

log = logging.getLogger(__name__)

POLL_S = 0.05  # a stop is heard within about this (plus one request) of arriving at the pendant


def read_count(client: httpx.Client, base_url: str) -> tuple[int, str] | None:
    """(stops heard, last cause) from a pendant's API; None when the other end is no pendant."""
    response = client.get(base_url.rstrip("/") + STOPS_PATH)
    if response.status_code != 200:
        return None
    heard = response.json()
    return int(heard["count"]), str(heard["last"])


class StopWatch:
    """Polls a pendant's stop count on a daemon thread; each new stop goes to `heard(cause)`."""

    def __init__(self, client: httpx.Client, base_url: str, heard: Callable[[str], None]) -> None:
        self._client = client
        self._base_url = base_url
        self._heard = heard
        self._done = threading.Event()
        self._thread: threading.Thread | None = None
        self._seen = 0
        self._seen_lock = threading.Lock()  # the watcher's thread and a failing step's poll_now

    def start(self) -> bool:
        """Begin watching; False (nothing started) when the other end does not count stops."""
        try:
            first = read_count(self._client, self._base_url)
        except (httpx.HTTPError, ValueError, KeyError, TypeError):
            first = None
        if first is None:
            return False
        self._seen = first[0]
        self._thread = threading.Thread(target=self._watch, name="pendant-stop-watch", daemon=True)
        self._thread.start()
        return True

    def poll_now(self) -> None:
        """Read the count at once (a step just failed: was it a stop on its way?)."""
        with self._seen_lock:
            self._check()

    def stop(self) -> None:
        self._done.set()
        if self._thread is not None:
            self._thread.join(timeout=1.0)

    def _watch(self) -> None:
        while not self._done.wait(POLL_S):
            with self._seen_lock:
                self._check()

    def _check(self) -> None:
        try:
            now = read_count(self._client, self._base_url)
        except (httpx.HTTPError, ValueError, KeyError, TypeError) as error:
            log.debug("reading the pendant's stops failed: %s", error)
            return
        if now is not None and now[0] != self._seen:
            self._seen = now[0]
            self._heard(now[1] or "a stop sent to the pendant")
