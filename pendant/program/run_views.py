"""Telling the views (every browser's Program tab, the teach bar) how a run goes, without the run waiting for
them.

The runner tells its listeners on the run's own thread. Each browser's panels redraw on such a call: with 60
browsers watching, every step waited for 60 redraws before it began (issue 37). Here, a step's progress
while the run stays RUNNING is redrawn on a thread of its own, the steps in between coalesced (the views read
the latest progress); a change of state (started, paused, stopped, failed, finished) is still shown before
the runner goes on, as before, so that whoever waits for a run to end sees its panels say how it ended.
Redraws never overlap: an older one cannot land after a newer one.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable

from pendant.program.runner import RunProgress, RunState

log = logging.getLogger(__name__)


class RunViews:
    """`changed(progress)` is the runner's listener; `redraw()` tells every view (it reads the latest)."""

    def __init__(self, redraw: Callable[[], None]) -> None:
        self._redraw = redraw
        self._drawing = threading.Lock()  # one redraw at a time, whichever thread asks
        self._shown: RunState | None = None
        self._wanted = threading.Event()  # a step's progress not yet redrawn
        self._thread: threading.Thread | None = None

    def changed(self, progress: RunProgress) -> None:
        within_run = progress.state is RunState.RUNNING and self._shown is RunState.RUNNING
        self._shown = progress.state
        if within_run:
            self._wanted.set()
            return
        if progress.state is RunState.RUNNING and self._thread is None:
            # Started once, as the first run begins (starting a thread can take long on a busy machine).
            self._thread = threading.Thread(target=self._drain, name="pendant-run-views", daemon=True)
            self._thread.start()
        self._draw()

    def _drain(self) -> None:
        while True:
            self._wanted.wait()
            self._wanted.clear()
            self._draw()

    def _draw(self) -> None:
        with self._drawing:
            try:
                self._redraw()
            except Exception:  # a broken view must not stop the run nor the other views
                log.exception("redrawing the run's views failed")
