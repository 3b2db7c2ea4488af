"""How long a piece of work keeps the other threads of its process waiting (the GIL): the most CPU time it
spends between two turns of a thread that wants to run every millisecond (a Freeze arriving is such a
thread). CPU time, not wall time: on a loaded machine the work's thread waiting for a core is not counted,
only what it did while nobody else could run Python."""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Callable
from typing import Any

TURN_S = 0.001  # the watching thread asks for a turn this often
LOWEST = 19  # niceness


def longest_hold_ms(work: Callable[[], Any]) -> tuple[float, Any]:
    """Run `work()` on a thread of its own: (the most CPU ms it ran between two turns of this thread, what
    it returned or raised)."""
    ready, go = threading.Event(), threading.Event()
    out: dict[str, Any] = {}

    def run() -> None:
        # The lowest priority for the work's thread: on a busy machine, it runs less while the watching
        # thread waits for a core, time that would otherwise count as held.
        os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), LOWEST)
        out["clock"] = time.pthread_getcpuclockid(threading.get_ident())
        ready.set()
        go.wait()
        try:
            out["result"] = work()
        except Exception as error:  # what it raised is part of the answer
            out["result"] = error
        out["end"] = time.thread_time()

    thread = threading.Thread(target=run, name="held-work")
    thread.start()
    ready.wait()
    clock = out["clock"]
    last, worst = time.clock_gettime(clock), 0.0
    go.set()
    while True:
        time.sleep(TURN_S)
        if "end" in out:
            break
        now = time.clock_gettime(clock)
        worst, last = max(worst, now - last), now
    worst = max(worst, out["end"] - last)
    thread.join()
    return worst * 1000, out["result"]
