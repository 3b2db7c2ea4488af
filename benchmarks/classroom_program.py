"""benchmarks/classroom.py --program: the operator runs a program from the page instead of holding a jog.

The pendant starts with its simulator writing down each move and output on its own clock
(tests/support/sim_step_log.py) and the program in its programs folder (tests/support/program_page.py: Move J
A, Wait 500 ms, DO1 high, Wait 500 ms, Move J B, Wait 500 ms, DO1 low, Wait 500 ms). The operator (a process
of its own, the first browser) opens it and presses Run with the loop count 0 (until Stop) as soon as it
has its page, and presses Stop at the end. A step is late by how much later it began than the previous
step's end + the wait between them: read for the operator alone, then with the viewers.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.churn import OperatorJob, pendant_from, percentile
from tests.support import sim_step_log
from tests.support.headless_viewer import open_viewer
from tests.support.program_page import WAIT_MS, ProgramOperator, save_classroom_program
from tests.support.sim_step_log import Logged, read_log, step_lateness

START_TIMEOUT_S = 150.0  # the Program tab comes after the operator's other panels: past a minute at load 30


@dataclass
class ProgramRun:
    """The log of the simulator and the run's last line."""

    log: Path
    ended: str = ""


@contextlib.contextmanager
def pendant_with_program(source: Path, prefix: str) -> Iterator[tuple[int, str, int, ProgramRun]]:
    """pendant_from's pendant, started through the step log with the program in its folder."""
    with tempfile.TemporaryDirectory(prefix="pendant-program-") as folder:
        programs, log = Path(folder) / "programs", Path(folder) / "steps.jsonl"
        programs.mkdir()
        save_classroom_program(programs)
        launcher = (str(Path(sim_step_log.__file__).resolve()), str(log))
        env = {"PENDANT_PROGRAMS_DIR": str(programs)}
        with pendant_from(source, prefix, launcher, env) as (ui, api, pid):
            yield ui, api, pid, ProgramRun(log)


async def operate(job: OperatorJob) -> str:
    """The operator (churn.operator_process runs it in a process of its own, as a tablet's page): Run, then
    Stop after the job's time or once its `finish` is set; the run's last line."""
    operator = ProgramOperator(await open_viewer(job.ui_port))
    operator.start()
    await operator.run(0, START_TIMEOUT_S)
    job.results.put("ready")
    if job.finish is None:
        await asyncio.sleep(job.seconds)
    else:
        await asyncio.to_thread(job.finish.wait, job.seconds)
    await operator.stop()
    try:
        ended = await operator.ended(START_TIMEOUT_S)
    finally:
        await operator.close()
    return ended


@dataclass
class Lateness:
    outputs: list[float]  # s; an output's start after the move before it arrived + the wait
    moves: list[float]  # s; a move's start after the output before it + the wait

    @property
    def all(self) -> list[float]:
        return self.outputs + self.moves


def lateness_within(logged: list[Logged], t0: float, t1: float) -> Lateness:
    """The lateness of the steps that began between `t0` and `t1` (monotonic clock: the simulator's)."""
    wait_s = WAIT_MS / 1000.0
    outputs, moves = [], []
    for before, step in itertools.pairwise(logged):
        if t0 <= step.t < t1:
            late_outputs, late_moves = step_lateness([before, step], wait_s)
            outputs += late_outputs
            moves += late_moves
    return Lateness(outputs, moves)


def summary(late: list[float]) -> str:
    """p50 / p99 / max in ms (and how many)."""
    if not late:
        return "-"
    ms = [x * 1000 for x in late]
    return f"{percentile(ms, 0.5):.0f} / {percentile(ms, 0.99):.0f} / {max(ms):.0f} ({len(ms)})"


def moving(run: ProgramRun, t0: float, t1: float) -> list[tuple[float, float]]:
    """The simulator's moves between `t0` and `t1`: (sent, arrived), clipped to the window."""
    return [
        (max(step.t, t0), min(step.end, t1))
        for step in read_log(run.log)
        if step.kind == "move" and step.end > t0 and step.t < t1
    ]


def windows(
    run: ProgramRun, alone: tuple[float, float], viewers: tuple[float, float]
) -> tuple[Lateness, Lateness]:
    """The steps' lateness with the operator alone, and with the viewers."""
    logged = read_log(run.log)
    return lateness_within(logged, *alone), lateness_within(logged, *viewers)
