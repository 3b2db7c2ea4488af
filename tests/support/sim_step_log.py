"""A program's steps timed from the controller's side.

`python tests/support/sim_step_log.py LOG PENDANT-ARGS...` runs `pendant` unchanged except that its embedded
simulator writes down, on its own clock, each motion it queues (when it was sent, when the arm will have
arrived) and each output it sets: one JSON line each, to LOG. `step_lateness` reads that back for a program
of moves and outputs separated by waits, and says how late each step began against when it was due (the
previous step's end + the wait between them).

Run as a script, this file imports nothing but `pendant` and the standard library (so it can start the
pendant of another checkout, for a benchmark's before / after).
"""

from __future__ import annotations

import itertools
import json
import sys
import threading
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Logged:
    """One thing the simulator did: a move (`t`: sent; `end`: arrived) or an output set (`t`)."""

    kind: str  # "move" or "output"
    t: float
    end: float
    level: str = ""  # an output's level


def _install(log_path: str) -> None:
    from pendant.sim.controller import SimController
    from pendant.sim.queue import MotionQueue

    lock = threading.Lock()
    out = open(log_path, "a", buffering=1)  # noqa: SIM115  # line-buffered, open for the process's life

    def write(record: dict[str, object]) -> None:
        with lock:
            out.write(json.dumps(record) + "\n")

    append, set_output = MotionQueue.append, SimController.set_output

    def logged_append(self: MotionQueue, motion, now: float) -> None:  # type: ignore[no-untyped-def]
        append(self, motion, now)
        if not motion.jog:
            write({"kind": "move", "t": now, "end": motion.t_end})

    def logged_set_output(self: SimController, port: int, level) -> None:  # type: ignore[no-untyped-def]
        set_output(self, port, level)
        now = self.clock.now()
        write({"kind": "output", "t": now, "end": now, "level": str(getattr(level, "value", level))})

    MotionQueue.append = logged_append  # type: ignore[method-assign]
    SimController.set_output = logged_set_output  # type: ignore[method-assign]


def read_log(path: Path) -> list[Logged]:
    if not path.exists():
        return []
    lines = [line for line in path.read_text().splitlines() if line.strip()]
    return [Logged(**json.loads(line)) for line in lines]


def step_lateness(logged: list[Logged], wait_s: float) -> tuple[list[float], list[float]]:
    """For a program whose moves and outputs alternate with a wait of `wait_s` after each: how late each
    output began after the move before it arrived + `wait_s` (the run sees an arrival by polling the arm,
    every 50 ms), and how late each move was sent after the output before it + `wait_s` (s, each list in
    the order they ran). Raises AssertionError when moves and outputs do not alternate."""
    outputs: list[float] = []
    moves: list[float] = []
    for before, step in itertools.pairwise(logged):
        assert before.kind != step.kind, f"two {step.kind}s in a row: {before} then {step}"
        late = step.t - (before.end + wait_s)
        (outputs if step.kind == "output" else moves).append(late)
    return outputs, moves


if __name__ == "__main__":
    del sys.path[0]  # this folder: its modules are the tests' helpers, not the pendant's
    _install(sys.argv[1])
    from pendant.cli import main

    sys.argv = ["pendant", *sys.argv[2:]]
    raise SystemExit(main())
