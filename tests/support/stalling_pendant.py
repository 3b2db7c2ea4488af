"""A pendant whose whole process stands still now and then, as a full garbage collection holds it.

`python tests/support/stalling_pendant.py STALL_MS EVERY_MS PENDANT-ARGS...` runs `pendant` unchanged beside
a thread that every EVERY_MS holds the interpreter lock for STALL_MS: a C call made without letting go of the
lock (libc's usleep through ctypes.PyDLL), so no other thread of the process runs meanwhile (the hold line's,
the deadman's watchdog, viser's loop), while the operator's browser, a process of its own, goes on sending.
With 100 browsers' panels a full collection held the pendant 114-139 ms (2-core machine, 3 Dec).

Run as a script, this file imports nothing but `pendant` and the standard library.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import sys
import threading
import time


def _stall_now_and_then(stall_ms: int, every_ms: int) -> None:
    usleep = ctypes.PyDLL(ctypes.util.find_library("c")).usleep  # PyDLL: the lock is kept during the call
    usleep.argtypes = [ctypes.c_uint]

    def run() -> None:
        while True:
            time.sleep((every_ms - stall_ms) / 1000.0)  # a stall begins every `every_ms`
            usleep(stall_ms * 1000)

    threading.Thread(target=run, name="test-stall", daemon=True).start()


if __name__ == "__main__":
    del sys.path[0]  # this folder: its modules are the tests' helpers, not the pendant's
    _stall_now_and_then(int(sys.argv[1]), int(sys.argv[2]))
    from pendant.cli import main

    sys.argv = ["pendant", *sys.argv[3:]]
    raise SystemExit(main())
