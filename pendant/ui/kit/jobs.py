"""Slow work a browser starts (loading a replay, a download): bounded, and off viser's callback pool.

viser runs every button's callback on one pool shared by every browser, Freeze's included; 40 clicks of
Replay filled it. Here a slow job runs on threads of its own, and a click only asks for one:
- one job at a time per browser: a second click while one runs is refused with a message, not queued;
- viewers (no control) share VIEWER_JOBS jobs at a time between them, refused beyond with a message;
- the operator's job never waits for the viewers' (its own thread is kept free).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor

import viser

log = logging.getLogger(__name__)

VIEWER_JOBS = 2  # viewers' replays and downloads at once, all viewers together
MSG_ONE_AT_A_TIME = "{running} is still running in this browser: wait for it to finish"
MSG_VIEWERS_BUSY = "the pendant is busy with {count} other viewers' jobs: try again in a moment"

IsOperator = Callable[[viser.ClientHandle | None], bool]


def _tell(client: viser.ClientHandle | None, title: str, body: str) -> None:
    log.warning("%s: %s", title, body)
    if client is not None:
        client.add_notification(title=title, body=body, color="red", auto_close_seconds=8.0)


class PageJobs:
    """`start(label, client, work)` runs `work()` on a job thread, or refuses (tells `client`) and returns
    None. A browser is keyed by its client id (None: the server itself, as headless tests call it)."""

    def __init__(self, is_operator: IsOperator = lambda client: True, viewer_jobs: int = VIEWER_JOBS) -> None:
        self._is_operator = is_operator
        self._viewer_jobs = viewer_jobs
        # The viewers' jobs, the operator's, and one more for a hand-over of control while jobs run.
        self._pool = ThreadPoolExecutor(max_workers=viewer_jobs + 2, thread_name_prefix="pendant-job")
        self._lock = threading.Lock()
        self._running: dict[int | None, tuple[str, bool]] = {}  # by browser: its job's label, a viewer's?

    def running(self, client: viser.ClientHandle | None) -> str | None:
        """The label of the job `client`'s browser runs now, or None."""
        with self._lock:
            job = self._running.get(_key(client))
        return job[0] if job is not None else None

    def start(
        self, label: str, client: viser.ClientHandle | None, work: Callable[[], object]
    ) -> Future[object] | None:
        key, viewer = _key(client), not self._is_operator(client)
        with self._lock:
            reason = self._refusal(key, viewer)
            if reason is None:
                self._running[key] = (label, viewer)
        if reason is not None:
            _tell(client, f"{label} refused", reason)
            return None

        def run() -> object:
            try:
                return work()
            except Exception as error:
                log.exception("%s failed", label)
                _tell(client, f"{label} failed", str(error) or type(error).__name__)
                raise
            finally:
                with self._lock:
                    self._running.pop(key, None)

        try:
            return self._pool.submit(run)
        except RuntimeError:  # shut down: the page is closing
            with self._lock:
                self._running.pop(key, None)
            return None

    def _refusal(self, key: int | None, viewer: bool) -> str | None:
        running = self._running.get(key)
        if running is not None:
            return MSG_ONE_AT_A_TIME.format(running=running[0])
        viewers = sum(1 for _, by_viewer in self._running.values() if by_viewer)
        if viewer and viewers >= self._viewer_jobs:
            return MSG_VIEWERS_BUSY.format(count=viewers)
        return None

    def shutdown(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)


def _key(client: viser.ClientHandle | None) -> int | None:
    return client.client_id if client is not None else None
