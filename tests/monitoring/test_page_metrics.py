"""What the page counts for Prometheus: program runs and failures, the arm going to an alarm state, page
commands, browsers connected. Scraped as Prometheus would, from the registry's text exposition."""

from __future__ import annotations

from pathlib import Path

from prometheus_client.parser import text_string_to_metric_families

from pendant.controller import MotionStatus
from pendant.eventlog import EventLog
from pendant.monitoring import PendantMetrics
from pendant.program import ProgramRunner, ProgramStore, ProgramWorkspace, RunState
from pendant.sim import FakeClock, Fault, SimController
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.activity import ActivityLog
from pendant.ui.page.roles import ControlDesk
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser
from tests.support.pages import headless_session, new_page
from tests.support.programs import POLL_S, POSE_A_DEG, settle, teach

WAIT_S = 10.0


def scraped(metrics: PendantMetrics) -> dict[str, float]:
    """`name{label="v"}` -> value, for the pendant's own counters (the arm's gauges left out)."""
    out = {}
    for family in text_string_to_metric_families(metrics.exposition().decode()):
        for sample in family.samples:
            labels = ",".join(f'{k}="{v}"' for k, v in sorted(sample.labels.items()))
            out[f"{sample.name}{{{labels}}}" if labels else sample.name] = sample.value
    return out


def test_program_runs_failures_and_alarms_are_counted(
    sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    metrics = PendantMetrics(sim, mode="sim", model="pulse75", robot_url=None)
    events = EventLog()
    metrics.watch(events)
    activity = ActivityLog(events, ControlDesk(events), metrics)
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S)
    workspace = ProgramWorkspace(ProgramStore(tmp_path / "programs"), runner)
    workspace.on_change(lambda change: activity.program_changed(workspace, change))
    teach(sim, clock, POSE_A_DEG, "ignored")
    workspace.record_from(sim)
    sim.reset()

    workspace.start_run(loops=1)
    assert runner.join(timeout=WAIT_S)
    settle(sim, clock)
    assert workspace.progress.state is RunState.FINISHED
    sim.inject_fault(Fault.ERROR)
    workspace.start_run(loops=1)
    assert runner.join(timeout=WAIT_S)
    assert workspace.progress.state is RunState.FAILED

    idle, failed = MotionStatus.IDLE, MotionStatus.MOTION_FAILED
    activity.state_changed(Snapshot(0.0, motion_status=idle), Snapshot(0.1, motion_status=failed))
    counts = scraped(metrics)
    assert counts["pendant_program_runs_total"] == 2
    assert counts["pendant_program_failures_total"] == 1
    assert counts['pendant_motion_failures_total{source="program"}'] == 1
    assert counts['pendant_motion_failures_total{source="controller"}'] == 1
    assert counts['pendant_events_total{kind="error"}'] == 2  # the program's failure and MOTION_FAILED


def test_viewers_and_page_commands_are_counted(sim: SimController) -> None:
    metrics = PendantMetrics(sim, mode="sim", model="pulse75", robot_url=None)
    page = new_page(sim, sim.arm, mode_line="sim", metrics=metrics)
    try:
        assert scraped(metrics)["pendant_viewers_connected"] == 0
        headless_session(page)
        assert scraped(metrics)["pendant_viewers_connected"] == 1
        page.desk.join(OPERATOR)
        page.desk.join(VIEWER)
        page.runner.submit("Home", lambda controller: controller.freeze(), None).result(timeout=WAIT_S)
        refused = page.runner.submit(
            "Relax", lambda controller: controller.relax(), FakeBrowser(VIEWER).handle
        )
        assert refused.exception() is not None
    finally:
        page.stop()
    counts = scraped(metrics)
    assert counts['pendant_commands_total{endpoint="Home",source="page",status="sent"}'] == 1
    assert counts['pendant_command_refusals_total{endpoint="Relax",source="page",status="refused"}'] == 1
