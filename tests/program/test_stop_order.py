"""The page's program Stop reaches a run by two ways: its announcement on the stop bus (`stop_heard`, which
alone leaves the run resumable, as any other stop does) and the runner's `stop` on the urgent thread (the
run ends for good). The run hears them in either order, on its own thread. Whichever comes first, it ends
for good, "Stopped at step N by Stop by browser #1", and never shows as resumable on the way (Retry / Skip
offered for a moment, a stop without its cause: seen behind the timed pass in CI, 27 Nov).

The Stop is sent through the page's CommandRunner (kit/commands.py) with a stop bus wired as the page wires
it, and the runner's thread is made to look at the worst moment: after the announcement, before the urgent
thread's `stop`. The runner's sleeps advance the simulator's fake clock."""

from __future__ import annotations

import threading
from concurrent.futures import Future
from typing import Any

import pytest

from pendant.controller import SignalLevel
from pendant.controller.stops import StopBus
from pendant.program import ProgramRunner, RunState, WaitInputStep, WaitStep
from pendant.program.runner import RunProgress
from pendant.sim import FakeClock, SimController
from pendant.ui.kit.commands import CommandRunner
from tests.support.programs import POLL_S, program_of
from tests.support.waiting import SAFETY_NET_S

CAUSE = "Stop by browser #1"
TIMEOUT_S = SAFETY_NET_S


class Browser:
    client_id = 1


def page_wiring(sim: SimController, runner: ProgramRunner) -> CommandRunner:
    """The page's CommandRunner and stop bus as pendant/ui/app.py wires them."""
    bus = StopBus()
    bus.subscribe(runner.stop_heard)
    commands = CommandRunner(sim)
    commands.on_stop = bus.notify
    return commands


def page_stop(commands: CommandRunner, runner: ProgramRunner, release: threading.Event) -> Future[object]:
    """The Program tab's Stop as run_section.py sends it, its urgent half held until `release` is set."""

    def on_urgent_thread(_: object) -> None:
        release.wait(TIMEOUT_S)
        runner.stop()

    browser: Any = Browser()  # what the CommandRunner reads of a viser client: its id
    return commands.submit("Stop", on_urgent_thread, browser, urgent=True, ending=runner.request_stop)


@pytest.mark.parametrize(
    "step", [WaitStep(ms=20_000), WaitInputStep(port=1, level=SignalLevel.HIGH, timeout_ms=20_000)]
)
@pytest.mark.parametrize("urgent_first", [False, True], ids=["announcement first", "urgent stop first"])
def test_the_page_stop_ends_the_run_for_good_whichever_half_it_hears_first(
    sim: SimController, clock: FakeClock, step: WaitStep | WaitInputStep, urgent_first: bool
) -> None:
    seen: list[RunProgress] = []
    release = threading.Event()
    pressed: list[bool] = []

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if runner.progress.state is RunState.RUNNING and clock.now() > 1.0 and not pressed:
            pressed.append(True)
            if urgent_first:
                release.set()
            sent = page_stop(commands, runner, release)
            if urgent_first:  # the urgent thread's stop lands before the run's next look
                sent.result(TIMEOUT_S)

    runner = ProgramRunner(sim, sleep=sleep, now=clock.now, poll_s=POLL_S)
    commands = page_wiring(sim, runner)
    runner.add_listener(seen.append)

    runner.run(program_of(step, WaitStep(ms=100)))
    stopped = runner.progress
    can_resume_before_urgent_stop = runner.can_resume
    release.set()
    commands.shutdown()

    assert pressed, "the run never got to the Stop"
    assert stopped.state is RunState.STOPPED
    assert stopped.message == f"Stopped at step 1 by {CAUSE}"
    assert not can_resume_before_urgent_stop  # Stop ends the run for good: no Retry or Skip
    resumable = [p for p in seen if p.state is RunState.STOPPED and p.failed_step is not None]
    assert resumable == [], "the run showed Retry / Skip on its way to its end"


def test_a_paused_run_stopped_from_the_page_is_never_resumable_on_the_way(
    sim: SimController, clock: FakeClock
) -> None:
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S)
    commands = page_wiring(sim, runner)
    seen: list[RunProgress] = []
    runner.step(program_of(WaitStep(ms=100), WaitStep(ms=100)))
    assert runner.progress.state is RunState.PAUSED
    runner.add_listener(seen.append)
    release = threading.Event()

    sent = page_stop(commands, runner, release)
    announced_only = runner.progress
    release.set()
    sent.result(TIMEOUT_S)
    commands.shutdown()

    assert announced_only.state is RunState.PAUSED  # the announcement alone left it to the Stop
    assert runner.progress.state is RunState.STOPPED
    assert not runner.can_resume
    assert [p for p in seen if p.failed_step is not None] == []
