"""A program runs while a classroom watches (issue 37). A real `pendant` process on loopback; 30 viewers read
every frame of viser's websocket, as browsers do (each with its panels built); the operator (the first
browser) opens a program in the page's Program tab and presses Run for 3 loops: Move J A, Wait 500 ms, DO1
high, Wait 500 ms, Move J B, Wait 500 ms, DO1 low, Wait 500 ms. Timed by the simulator on its own clock
(tests/support/sim_step_log.py), the moves and outputs happen in that order, none begins more than half a
second after it was due (a 500 ms wait that lasts over a second: a user sees that), and the run ends
"Finished". How late the steps are with 1 to 100 viewers: `benchmarks/classroom.py --program`."""

from __future__ import annotations

import asyncio
from pathlib import Path

import pytest

from pendant.controller import SignalLevel
from tests.support import sim_step_log
from tests.support.headless_viewer import ViewerCounts, open_viewer, viewer
from tests.support.launchers import Pendant, running_pendant_ui
from tests.support.program_page import FINISHED, WAIT_MS, ProgramOperator, save_classroom_program
from tests.support.sim_step_log import read_log, step_lateness

pytestmark = pytest.mark.measures  # real time: how late a step begins beside 30 browsers

VIEWERS = 30
LOOPS = 3
LATE_S = 0.5  # a 500 ms wait that lasts more than a second
PAGE_TIMEOUT_S = 120.0  # generous: the machine may be loaded; the page's speed is not what is tested
RUN_TIMEOUT_S = 120.0


async def _run_beside_viewers(pendant: Pendant) -> tuple[str, list[ViewerCounts]]:
    """The operator first (it gets control), then the viewers; Run; the run's last line."""
    operator = ProgramOperator(await open_viewer(pendant.ui_port))
    operator.start()
    stop = asyncio.Event()
    counts = [ViewerCounts() for _ in range(VIEWERS)]
    url = f"ws://127.0.0.1:{pendant.ui_port}/"
    watching = [asyncio.create_task(viewer(url, c, stop)) for c in counts]
    try:
        async with asyncio.timeout(PAGE_TIMEOUT_S):  # its Program tab; the viewers' every tab
            await operator.controls.wait()
            await asyncio.gather(*(c.whole_panel.wait() for c in counts))
        await operator.run(LOOPS, PAGE_TIMEOUT_S)
        return await operator.ended(RUN_TIMEOUT_S), counts
    finally:
        stop.set()
        await asyncio.gather(*watching)
        await operator.close()


def test_a_program_run_keeps_its_timing_while_30_viewers_watch(tmp_path: Path) -> None:
    programs, log = tmp_path / "programs", tmp_path / "steps.jsonl"
    programs.mkdir()
    save_classroom_program(programs)
    launcher = (str(Path(sim_step_log.__file__)), str(log))
    with running_pendant_ui(env={"PENDANT_PROGRAMS_DIR": str(programs)}, launcher=launcher) as pendant:
        ended, counts = asyncio.run(_run_beside_viewers(pendant))

    assert ended == FINISHED
    assert all(c.bytes_received > 0 for c in counts), "a viewer received nothing"
    logged = read_log(log)
    assert [s.kind for s in logged] == ["move", "output"] * 2 * LOOPS
    assert [s.level for s in logged if s.kind == "output"] == [SignalLevel.HIGH, SignalLevel.LOW] * LOOPS
    outputs, moves = step_lateness(logged, WAIT_MS / 1000.0)
    late = {
        f"{kind} {k + 1}": round(s, 3)
        for kind, lates in (("output", outputs), ("move", moves))
        for k, s in enumerate(lates)
        if s > LATE_S
    }
    assert not late, f"steps late by more than {LATE_S} s (s): {late}"
