"""A classroom of viewers in a process of its own, as a room's phones are on devices of their own: each reads
every frame of the page's websocket (tests/support/headless_viewer.py) with its whole panel built before the
test goes on, and when the room ends, says when the arm's pose came to each."""

from __future__ import annotations

import asyncio
import contextlib
import multiprocessing
import queue
import time
from multiprocessing.synchronize import Event

from tests.support.headless_viewer import ViewerCounts, viewer


def _watch(
    port: int, viewers: int, ready: Event, done: Event, results: multiprocessing.Queue, timeout_s: float
) -> None:
    """The viewers, in a spawned process: `ready` once every panel is built, reading until `done`; then
    each viewer's arm update times (monotonic, shared by the machine's processes) go to `results`."""

    async def run() -> list[list[float]]:
        stop = asyncio.Event()
        counts = [ViewerCounts() for _ in range(viewers)]
        reading = [asyncio.create_task(viewer(f"ws://127.0.0.1:{port}/", c, stop)) for c in counts]
        async with asyncio.timeout(timeout_s):
            await asyncio.gather(*(c.whole_panel.wait() for c in counts))
        ready.set()
        await asyncio.to_thread(done.wait, timeout_s)
        stop.set()
        await asyncio.gather(*reading, return_exceptions=True)
        return [c.state_times for c in counts]

    results.put(asyncio.run(run()))


class Room:
    """`viewers` browsers of the page on `port`; `timeout_s` bounds their panels and how long they watch."""

    def __init__(self, port: int, viewers: int, timeout_s: float) -> None:
        spawn = multiprocessing.get_context("spawn")
        self._ready, self._done, self._results = spawn.Event(), spawn.Event(), spawn.Queue()
        self._timeout_s = timeout_s
        self._collected = False
        self._process = spawn.Process(
            target=_watch,
            args=(port, viewers, self._ready, self._done, self._results, timeout_s),
            daemon=True,
        )

    def open(self) -> None:
        """The viewers come, and every one has its whole panel (or AssertionError)."""
        self._process.start()
        assert self._ready.wait(self._timeout_s), "the viewers' panels were not built"

    def arm_update_times(self) -> list[list[float]]:
        """The viewers stop watching: when each saw the arm's pose (monotonic s)."""
        self._done.set()
        updates: list[list[float]] = self._results.get(True, self._timeout_s)
        self._collected = True
        return updates

    def close(self) -> None:
        self._done.set()
        if self._process.pid is None:
            return  # never opened
        # Read what it sends if nobody has: a child exits only once its queue's data is in the pipe.
        until = time.monotonic() + self._timeout_s
        while not self._collected and self._process.is_alive() and time.monotonic() < until:
            with contextlib.suppress(queue.Empty):
                self._results.get(True, 0.5)
                self._collected = True
        self._process.join(max(0.0, until - time.monotonic()))
