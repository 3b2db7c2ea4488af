"""Per-client bookkeeping of refusals: wrong tokens slowed down, and refusals logged once per burst.

`FailedAttempts`: the first few wrong tokens from an address cost nothing; after that each further check from
that address waits for its turn, one per `interval_s`, however many connections it opens (guesses are
serialised, not merely delayed). A turn further away than `max_wait_s` is refused at once with 429 instead of
holding the connection. A right token, or `forget_after_s` without a wrong one, clears the address.

`BurstLog`: a client refused again and again (a script in a loop, a guesser) gets one event-log line for the
first refusal of a burst; the next line, after `quiet_s` without refusals, says how many were not logged.
"""

from __future__ import annotations

import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass

FREE_FAILURES = 5
INTERVAL_S = 1.0
MAX_WAIT_S = 10.0
FORGET_AFTER_S = 60.0
QUIET_S = 10.0
MAX_CLIENTS = 4096  # bounded memory whatever the number of addresses


@dataclass
class _Record:
    failures: int = 0
    next_turn: float = 0.0
    last_failure: float = 0.0


class FailedAttempts:
    """Wrong access tokens per client address. Thread-safe (the API's event loop and the page's threads)."""

    def __init__(
        self,
        free: int = FREE_FAILURES,
        interval_s: float = INTERVAL_S,
        max_wait_s: float = MAX_WAIT_S,
        forget_after_s: float = FORGET_AFTER_S,
        now: Callable[[], float] = time.monotonic,
    ) -> None:
        self.free, self.interval_s, self.max_wait_s = free, interval_s, max_wait_s
        self.forget_after_s = forget_after_s
        self._now = now
        self._records: OrderedDict[str, _Record] = OrderedDict()
        self._lock = threading.Lock()

    def wait_before_check(self, client: str) -> float | None:
        """Seconds `client` must wait before its token is checked (0: at once); None: refuse without checking
        (its turn is more than `max_wait_s` away)."""
        now = self._now()
        with self._lock:
            record = self._records.get(client)
            if record is None:
                return 0.0
            if now - record.last_failure > self.forget_after_s:
                del self._records[client]
                return 0.0
            if record.failures < self.free:
                return 0.0
            turn = max(now, record.next_turn)
            if turn - now > self.max_wait_s:
                return None
            record.next_turn = turn + self.interval_s
            return turn - now

    def failed(self, client: str) -> None:
        now = self._now()
        with self._lock:
            record = self._records.pop(client, None) or _Record()
            record.failures += 1
            record.last_failure = now
            if record.failures >= self.free:
                record.next_turn = max(record.next_turn, now + self.interval_s)
            self._records[client] = record  # most recent last: the oldest go first when full
            while len(self._records) > MAX_CLIENTS:
                self._records.popitem(last=False)

    def succeeded(self, client: str) -> None:
        with self._lock:
            self._records.pop(client, None)


@dataclass
class _Burst:
    last: float
    unlogged: int = 0


class BurstLog:
    """Decides which refusals of a client reach the event log: the first of each burst."""

    def __init__(self, quiet_s: float = QUIET_S, now: Callable[[], float] = time.monotonic) -> None:
        self.quiet_s = quiet_s
        self._now = now
        self._bursts: OrderedDict[str, _Burst] = OrderedDict()
        self._lock = threading.Lock()

    def note(self, client: str) -> int | None:
        """None: stay quiet (the client's burst goes on); else log, and this many refusals were not logged
        since the previous line."""
        now = self._now()
        with self._lock:
            burst = self._bursts.pop(client, None)
            if burst is not None and now - burst.last <= self.quiet_s:
                burst.last = now
                burst.unlogged += 1
                self._bursts[client] = burst
                return None
            self._bursts[client] = _Burst(last=now)
            while len(self._bursts) > MAX_CLIENTS:
                self._bursts.popitem(last=False)
            return burst.unlogged if burst is not None else 0
