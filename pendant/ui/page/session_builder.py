"""Builds the browsers' panels one at a time, on a thread of its own, the newest browser first.

A browser's panels are some 800 GUI messages, ~0.5 s of Python. viser runs each connect callback on its
callback pool (32 threads), the pool that also runs every button's callback, Freeze's included. Under many
browsers connecting and leaving, 32 builds at once (most for browsers that had already left) took the pool
and the interpreter: a new viewer waited 10-22 s for its page and a held jog's confirmations came late
enough for the deadman to stop it (benchmarks/churn.py).

Here the connect callback sends Freeze at once (show_first_panel: a few messages, so every page has it within
a moment) and queues the rest. One thread builds: a browser that left while waiting is
never built; the newest waiting browser goes first (the one most likely still there, and the person who just
opened the page waits one build, not one per browser before them), except that a browser that has waited
OLDEST_WAIT_S goes before newer ones, so nobody who stays waits for ever. While the operator holds a jog,
builds wait, each browser at most HOLD_BACK_MAX_S from its arrival (the longest waiting first): a jog held
for minutes while newcomers arrive every 2 s then keeps each waiting that long, not one wait per build
before it (with the wait counted per build the queue grew for as long as the hold lasted: a newcomer's
whole panel took 13 s median, 25 s p95, beside 60 viewers: benchmarks/classroom.py).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import viser

from pendant.ui.kit.commands import CommandRunner, add_freeze_button

log = logging.getLogger(__name__)

OLDEST_WAIT_S = 10.0
# While the operator holds a jog, builds wait (newcomers already have Freeze and the 3D view): a build is
# ~0.2 s of Python under the interpreter's lock, and the hold's confirmations must reach the deadman in
# time; most jog presses are shorter than this. A browser waits at most this long from its arrival, so a
# jog held for minutes does not leave the others without their panels (issue 37: <= 3 s p95).
HOLD_BACK_MAX_S = 2.0
HOLD_BACK_POLL_S = 0.05
# Builds one after another take at most this share of the time (see SessionBuilder._rest).
BUILD_SHARE = 0.5
MAX_REST_S = 2.0
STOP_TIMEOUT_S = 5.0
LOADING_NOTE = "*Loading the panels…*"  # under Freeze while the browser waits for the rest


@dataclass(frozen=True)
class FirstPanel:
    """What a browser gets the moment it connects: Freeze (the page is never without it) and a note."""

    freeze: viser.GuiButtonHandle
    loading: viser.GuiMarkdownHandle


def show_first_panel(client: viser.ClientHandle, runner: CommandRunner) -> FirstPanel:
    """Freeze and the loading note on `client`'s page: a few messages, sent before it waits for a build."""
    return FirstPanel(add_freeze_button(client, runner), client.gui.add_markdown(LOADING_NOTE))


@dataclass(frozen=True)
class _Waiting:
    build: Callable[[], None]
    since: float


class SessionBuilder:
    """`submit(client_id, build)` queues a browser's build; the builder thread runs it if the browser is
    still there. `cancel(client_id)` (the browser left): True when it was still waiting, so never built."""

    def __init__(
        self,
        *,
        oldest_wait_s: float = OLDEST_WAIT_S,
        clock: Callable[[], float] = time.monotonic,
        hold_back: Callable[[], bool] = lambda: False,
    ) -> None:
        self._oldest_wait_s = oldest_wait_s
        self._hold_back = hold_back  # True while builds should wait (the operator is jogging)
        self._clock = clock
        self._waiting: dict[int, _Waiting] = {}  # by client id, in arrival order
        self._wake = threading.Condition()
        self._stopped = False
        self._thread = threading.Thread(target=self._run, name="pendant-sessions", daemon=True)
        self._thread.start()

    def submit(self, client_id: int, build: Callable[[], None]) -> None:
        with self._wake:
            self._waiting[client_id] = _Waiting(build, self._clock())
            self._wake.notify()

    def cancel(self, client_id: int) -> bool:
        with self._wake:
            return self._waiting.pop(client_id, None) is not None

    def waiting(self) -> int:
        with self._wake:
            return len(self._waiting)

    def stop(self) -> None:
        with self._wake:
            self._stopped = True
            self._waiting.clear()
            self._wake.notify()
        if self._thread is not threading.current_thread():
            self._thread.join(STOP_TIMEOUT_S)

    def _next(self) -> tuple[int, Callable[[], None]] | None:
        """The next browser to build (None: stopped): the newest, unless the oldest has waited too long;
        while the operator jogs, none until the longest waiting has waited HOLD_BACK_MAX_S, and then it."""
        with self._wake:
            while True:
                while not self._waiting and not self._stopped:
                    self._wake.wait()
                if self._stopped:
                    return None
                oldest = next(iter(self._waiting))
                waited = self._clock() - self._waiting[oldest].since
                if self._holding_back():
                    if waited < HOLD_BACK_MAX_S:
                        # A browser may leave, or the jog end, meanwhile: look again.
                        self._wake.wait(min(HOLD_BACK_POLL_S, HOLD_BACK_MAX_S - waited))
                        continue
                    chosen = oldest  # it has waited its longest
                else:
                    chosen = oldest if waited >= self._oldest_wait_s else next(reversed(self._waiting))
                return chosen, self._waiting.pop(chosen).build

    def _holding_back(self) -> bool:
        try:
            return bool(self._hold_back())
        except Exception:  # a broken check must not stop every build
            log.exception("the builder's hold-back check failed")
            return False

    def _run(self) -> None:
        while (job := self._next()) is not None:
            client_id, build = job
            started = self._clock()
            try:
                build()
            except Exception:  # one browser's broken connection must not keep the others waiting
                log.exception("building the panels of browser %s failed", client_id)
            self._rest(self._clock() - started)

    def _rest(self, build_s: float) -> None:
        """With more browsers waiting, as long again as the last build took before the next: builds back to
        back took the interpreter from everything else (100 browsers coming and going: the pendant at 1.1
        cores, a newcomer's Freeze 2.1 s, benchmarks/churn.py); at most half of it, they leave the rest."""
        until = time.monotonic() + min(build_s * (1.0 / BUILD_SHARE - 1.0), MAX_REST_S)
        with self._wake:  # a newcomer's submit wakes it: it rests on unless stopped
            while self._waiting and not self._stopped and (left := until - time.monotonic()) > 0:
                self._wake.wait(left)
