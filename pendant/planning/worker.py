"""The API's pre-flights run in a process of their own (issue #32).

Parsing and validating a 5 MB program body, and checking it on the twin, are long calls into C that hold
the GIL for hundreds of milliseconds at a time: in the server's process they held up PUT /freeze by up to
2 s. Here the server only passes bytes through a pipe, so its event loop stays free; a pre-flight past its
budget, or one running when the pendant quits, is ended by ending the process (at once, whatever it is in).

The process starts at the first pre-flight (about a second: it imports the planner) and stays for the next
ones; it exits by itself after IDLE_S without work, or when the server's end of the pipe closes.

The exchange, one pre-flight at a time: the server sends the body; the worker answers an Outcome (refused)
or READY; the server then sends the arm's state (read with GETs, only for a valid body; None when it cannot
be read) and the worker answers an Outcome (the report, or the reason it is refused).
"""

from __future__ import annotations

import contextlib
import json
import multiprocessing
import os
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from multiprocessing.connection import Connection
from multiprocessing.process import BaseProcess
from pathlib import Path

from pendant.planning.budget import MAX_WALL_S, Budget
from pendant.planning.twin import TwinSeed

IDLE_S = 300.0
START_TIMEOUT_S = 60.0  # a loaded machine imports the planner in seconds, not a minute
# Beyond the worker's own wall-time check (which answers 422 itself): a call that never returns to Python.
HARD_MARGIN_S = 10.0
POLL_S = 0.05
WORKER_NICENESS = 10
READY = "ready"
MSG_QUITTING = "the pendant is quitting: pre-flights are stopped"
MSG_WORKER_LOST = "the pre-flight process ended unexpectedly: {why}"
MSG_TOO_LONG = f"the pre-flight took longer than {MAX_WALL_S:g} s and was stopped: check a shorter program"


@dataclass(frozen=True)
class Outcome:
    """What to answer: a status and a JSON body (the report, or the reason as a JSON string)."""

    status: int
    body: bytes

    @staticmethod
    def refused(status: int, reason: str) -> Outcome:
        return Outcome(status, json.dumps(reason).encode())


@dataclass(frozen=True)
class Job:
    """What the worker needs besides the body: the arm model and the folder Call steps open."""

    model: str
    programs_dir: str
    max_wall_s: float = MAX_WALL_S


class PreflightWorker:
    """Runs one pre-flight at a time in a child process; `cancel()` (when quitting) ends it at once."""

    def __init__(self, idle_s: float = IDLE_S) -> None:
        self.idle_s = idle_s
        self._lock = threading.Lock()  # one pre-flight at a time, on one pipe
        self._process: BaseProcess | None = None
        self._conn: Connection | None = None
        self._cancelled = threading.Event()

    @property
    def pid(self) -> int | None:
        process = self._process
        return process.pid if process is not None and process.is_alive() else None

    def claim(self) -> bool:
        """Take the turn (False while another pre-flight has it): the server claims it before it reads a
        body, so that a busy pendant answers 409 without holding several 5 MB bodies at once."""
        return self._lock.acquire(blocking=False)

    def release(self) -> None:
        """Give the turn back (after `run`, or when the body could not be read)."""
        self._lock.release()

    def cancel(self) -> None:
        """Stop the running pre-flight (it answers 503) and refuse new ones: the pendant is quitting."""
        self._cancelled.set()
        self._end()

    def close(self) -> None:
        self._end()

    # --- the server's side ----------------------------------------------------------------------------
    def run(self, body: bytes, job: Job, read_seed: Callable[[], TwinSeed | Outcome]) -> Outcome:
        """The pre-flight of `body`, by the caller that holds the turn (`claim`). `read_seed` is called
        once the body is valid: the arm's state, or an Outcome to answer instead."""
        if self._cancelled.is_set():
            return Outcome.refused(503, MSG_QUITTING)
        conn = self._connection()
        try:
            conn.send_bytes(body)  # as bytes: nothing pickled or parsed on this side
            conn.send(job)
            answer = self._answer(conn, START_TIMEOUT_S + job.max_wall_s)
            if answer == READY:
                seed = read_seed()
                if isinstance(seed, Outcome):
                    conn.send(None)  # the worker drops the request
                    self._answer(conn, job.max_wall_s)
                    return seed
                conn.send(seed)
                answer = self._answer(conn, job.max_wall_s + HARD_MARGIN_S)
        except _Timeout:
            self._end()
            return Outcome.refused(422, MSG_TOO_LONG)
        except (EOFError, OSError) as error:
            self._end()
            if self._cancelled.is_set():
                return Outcome.refused(503, MSG_QUITTING)
            return Outcome.refused(500, MSG_WORKER_LOST.format(why=error or "no answer"))
        if not isinstance(answer, Outcome):
            self._end()
            return Outcome.refused(500, MSG_WORKER_LOST.format(why=f"it answered {answer!r}"))
        return answer

    def _answer(self, conn: Connection, timeout_s: float) -> Outcome | str | None:
        deadline = time.monotonic() + timeout_s
        while not conn.poll(POLL_S):
            if self._cancelled.is_set():
                raise EOFError(MSG_QUITTING)
            if time.monotonic() > deadline:
                raise _Timeout
        answer: Outcome | str | None = conn.recv()
        return answer

    def _connection(self) -> Connection:
        process, conn = self._process, self._conn
        if process is not None and conn is not None and process.is_alive():
            return conn
        self._end()
        context = multiprocessing.get_context("spawn")  # never fork a process full of threads
        ours, theirs = context.Pipe()
        process = context.Process(
            target=serve, args=(theirs, self.idle_s), name="pendant-preflight", daemon=True
        )
        process.start()
        theirs.close()
        self._process, self._conn = process, ours
        return ours

    def _end(self) -> None:
        process, conn = self._process, self._conn
        self._process = self._conn = None
        if process is not None and process.is_alive():
            process.kill()
            process.join(timeout=5.0)
        if conn is not None:
            conn.close()


class _Timeout(Exception):
    pass


# --- the worker's side (runs in the child process) ------------------------------------------------------
def serve(conn: Connection, idle_s: float) -> None:
    """The child's loop: one pre-flight per request, until idle for `idle_s` or the pipe closes."""
    with contextlib.suppress(OSError):
        os.nice(WORKER_NICENESS)  # on a busy machine the server (and PUT /freeze) gets the CPU first
    try:
        while conn.poll(idle_s):
            body = conn.recv_bytes()
            job: Job = conn.recv()
            try:
                answer = _check(body, job, conn)
            except (EOFError, OSError):
                raise
            except Exception as error:  # a bug: said in the answer (and the traceback on stderr)
                traceback.print_exc()
                answer = Outcome.refused(500, f"the pre-flight failed: {error!r}")
            conn.send(answer)
    except (EOFError, OSError, KeyboardInterrupt):
        pass


def _check(body: bytes, job: Job, conn: Connection) -> Outcome | None:
    from pendant.planning.preflight import PreflightOverBudget, PreflightRefused, preflight
    from pendant.planning.preflight_body import parse_request
    from pendant.program.files import ProgramStore

    try:
        request = parse_request(body)
    except PreflightRefused as error:
        return Outcome.refused(400, str(error))
    conn.send(READY)
    seed: TwinSeed | None = conn.recv()
    if seed is None:
        return None  # the server could not read the arm: it answers that itself
    options = request.options
    if options.cell is not None:
        seed = seed.with_cell(options.cell.obstacles, options.cell.tool_shape)
    try:
        report = preflight(
            request.program,
            seed,
            model=job.model,
            load=ProgramStore(Path(job.programs_dir)).load,
            inputs=options.inputs,
            loop_passes=options.while_loop_passes,
            budget=Budget(max_wall_s=job.max_wall_s),
        )
    except PreflightOverBudget as error:
        return Outcome.refused(422, str(error))
    except PreflightRefused as error:
        return Outcome.refused(400, str(error))
    return Outcome(200, json.dumps(report.as_json()).encode())
