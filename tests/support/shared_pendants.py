"""Pendant processes shared by the browser tests of one pytest process (one xdist worker), reset between test
modules instead of started for each (a start costs ~5 s of CPU and 5-35 s of wall on this 2-core machine).

A pendant is handed out again only when it is as a fresh one would be, checked on what anybody can see: no
browser connected any more, the simulator reset (home, IDLE, no fault, IO low, no obstacle, default tool and
base), its programs folder, recordings and saved cells untouched since it started (the program on screen,
its run and its banner live in the process: an edited program means a new process), and no test failed
while it was out.
Anything else: it is stopped (in the background) and a new one started.
"""

from __future__ import annotations

import contextlib
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path

import httpx

from pendant.cell.file import CELLS_DIR_ENV
from pendant.monitoring import DATA_DIR_ENV

from .launchers import Pendant, running_pendant_ui
from .waiting import wait_until

VIEWERS_GONE_S = 30.0  # the last module's pages closed: their websockets end within a moment
RESET_S = 30.0
Files = frozenset[tuple[str, int, int]]


def _files(folder: Path) -> Files:
    """Every file under `folder` with its size and modification time (nothing, if it does not exist)."""
    if not folder.exists():
        return frozenset()
    return frozenset(
        (str(path.relative_to(folder)), stat.st_size, stat.st_mtime_ns)
        for path in folder.rglob("*")
        if path.is_file() and (stat := path.stat())
    )


def viewers(pendant: Pendant) -> int:
    """Browsers showing the page, as GET /metrics counts them."""
    for line in pendant.api.get("/metrics").text.splitlines():
        if line.startswith("pendant_viewers_connected "):
            return int(float(line.split()[1]))
    raise AssertionError("no pendant_viewers_connected on /metrics")


def reset_simulator(pendant: Pendant) -> None:
    """Stop any motion, then the simulator's power-on state; wait until it says IDLE."""
    pendant.api.put("/freeze").raise_for_status()
    pendant.api.put("/sim/reset").raise_for_status()
    wait_until(lambda: pendant.status() == "IDLE", RESET_S, "the reset simulator at rest")


class _Running:
    """One pendant process, the stack that stops it, and its folders' contents when it was started."""

    def __init__(self, flags: tuple[str, ...]) -> None:
        self.stack = contextlib.ExitStack()
        folder = Path(self.stack.enter_context(tempfile.TemporaryDirectory(prefix="pendant-shared-")))
        programs, data, cells = folder / "programs", folder / "data", folder / "cells"
        for made in (programs, data, cells):
            made.mkdir()
        try:
            self.pendant = self.stack.enter_context(
                running_pendant_ui(
                    "--programs",
                    str(programs),
                    *flags,
                    env={DATA_DIR_ENV: str(data), CELLS_DIR_ENV: str(cells)},
                )
            )
        except BaseException:
            self.stack.close()
            raise
        self.pendant.programs, self.pendant.data, self.cells = programs, data, cells
        self.started_with = self.state()
        self.tainted = False

    def state(self) -> tuple[Files, Files, Files]:
        return _files(self.pendant.programs), _files(self.pendant.data / "recordings"), _files(self.cells)

    def reusable(self) -> bool:
        """As a fresh one would be (see the module's doc); the simulator is reset on the way."""
        if self.tainted or self.pendant.process is None or self.pendant.process.poll() is not None:
            return False
        try:
            wait_until(lambda: viewers(self.pendant) == 0, VIEWERS_GONE_S, "the last pages to leave")
            reset_simulator(self.pendant)
        except (TimeoutError, httpx.HTTPError):
            return False
        return self.state() == self.started_with


class SharedPendants:
    """`get(flags)`: a running pendant (`pendant --programs DIR FLAGS...`, its data folder of its own),
    `.programs` and `.data` set; reused while reusable, else replaced. `taint(pendant)`: never reuse it.
    `close()` stops them all."""

    def __init__(self) -> None:
        self._running: dict[tuple[str, ...], _Running] = {}
        self._stopping: list[threading.Thread] = []

    def get(self, *flags: str) -> Pendant:
        running = self._running.get(flags)
        if running is not None and not running.reusable():
            self._stop_in_background(self._running.pop(flags))
            running = None
        if running is None:
            running = self._running[flags] = _Running(flags)
        return running.pendant

    def taint(self, pendant: Pendant) -> None:
        for running in self._running.values():
            if running.pendant is pendant:
                running.tainted = True

    def _stop_in_background(self, running: _Running) -> None:
        """A pendant takes seconds to stop (SIGTERM, then its threads): the next one starts meanwhile."""
        thread = threading.Thread(target=running.stack.close, name="pendant-stop", daemon=True)
        thread.start()
        self._stopping.append(thread)

    def close(self) -> None:
        for running in self._running.values():
            self._stop_in_background(running)
        self._running.clear()
        for thread in self._stopping:
            thread.join()


@contextlib.contextmanager
def shared_pendants() -> Iterator[SharedPendants]:
    pool = SharedPendants()
    try:
        yield pool
    finally:
        pool.close()


# The time scale of the browser tests that are not about real time (`@pytest.mark.time_scale(NOT_REAL_TIME)`):
# motions 5 times faster, while a page's clicks and the API's polling (tens of ms on a loaded machine) still
# come well inside a motion.
NOT_REAL_TIME = 5.0
