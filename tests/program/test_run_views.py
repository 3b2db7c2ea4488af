"""A running program does not wait for the views that show its progress (issue 37): every browser's Program
tab redraws as the run goes, and with a classroom watching, each step waited for all of those redraws
before it began (60 browsers: 93 ms a step, up to 0.95 s on a loaded machine). Here one view is stuck
redrawing; the steps go on, and once the view is back it is told how the run ended."""

from __future__ import annotations

import threading
from pathlib import Path

from pendant.controller import SignalLevel
from pendant.program import (
    Change,
    OutputStep,
    ProgramRunner,
    ProgramStore,
    ProgramWorkspace,
    RunState,
    WaitInputStep,
    WaitStep,
)
from pendant.sim import SimController
from tests.support.waiting import SAFETY_NET_S, wait_until

WAIT_S = SAFETY_NET_S
POLL_S = 0.01
HIGH, LOW = SignalLevel.HIGH, SignalLevel.LOW


def test_the_steps_go_on_while_a_view_is_stuck_redrawing(sim: SimController, tmp_path: Path) -> None:
    # On the real clock: the run waits for DI1 (a step in progress) while the view gets stuck showing it.
    workspace = ProgramWorkspace(ProgramStore(tmp_path), ProgramRunner(sim, poll_s=POLL_S))
    steps = (
        WaitInputStep(port=1, level=HIGH, timeout_ms=60_000),
        OutputStep(port=1, level=HIGH),
        WaitStep(ms=100),
        OutputStep(port=2, level=HIGH),
        WaitStep(ms=100),
        OutputStep(port=1, level=LOW),
    )
    for step in steps:
        workspace.insert_step(step)
    stuck, back = threading.Event(), threading.Event()
    shown: list[str] = []

    def slow_view(change: Change) -> None:
        if change is not Change.RUN:
            return
        message = workspace.progress.message
        shown.append(message)
        if message.startswith("Running step"):  # a step's progress: this view takes its time
            stuck.set()
            back.wait(WAIT_S)

    workspace.on_change(slow_view)
    workspace.start_run()
    try:
        wait_until(stuck.is_set, WAIT_S, "the view stuck on the step waiting for DI1")
        sim.set_input(1, HIGH)
        done = lambda: sim.get_output(2) is HIGH and sim.get_output(1) is LOW  # noqa: E731
        wait_until(done, WAIT_S, "the program's outputs, the view still stuck")
    finally:
        back.set()
    assert workspace.runner.join(WAIT_S)
    assert workspace.progress.state is RunState.FINISHED
    wait_until(lambda: shown[-1] == "Finished", WAIT_S, "the view told the run finished")
