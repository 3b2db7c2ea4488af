"""What the page counts for Prometheus: program runs and failures, the arm going to an alarm state, page
commands, browsers connected. Scraped as Prometheus would, from the registry's text exposition."""

from __future__ import annotations

from pathlib import Path

from prometheus_client.parser import text_string_to_metric_families

from pendant.controller import MotionStatus
from pendant.eventlog import EventKind, EventLog
from pendant.monitoring import PendantMetrics
from pendant.monitoring.metrics import PAGE_COMMANDS
from pendant.program import ProgramRunner, ProgramStore, ProgramWorkspace, RunState
from pendant.sim import FakeClock, Fault, SimController
from pendant.ui.jog.record_panel import RECORD_LABEL
from pendant.ui.kit.commands import freeze
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.activity import ActivityLog
from pendant.ui.page.roles import ControlDesk
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser
from tests.support.pages import headless_session, new_page
from tests.support.programs import POLL_S, POSE_A_DEG, settle, teach
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S


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


def page_series(metrics: PendantMetrics) -> dict[tuple[str, str, str], float]:
    """(counter, endpoint, status) -> value of the page's command series."""
    return {
        (sample.name, sample.labels["endpoint"], sample.labels["status"]): sample.value
        for family in text_string_to_metric_families(metrics.exposition().decode())
        for sample in family.samples
        if sample.labels.get("source") == "page" and "endpoint" in sample.labels
    }


def test_a_page_shows_every_command_series_at_zero_and_names_make_no_new_ones(sim: SimController) -> None:
    """rate() and increase() need a sample before the first event: a page's commands exist at 0 from the
    start, by name and outcome; the names in a label (an obstacle's, a port's number) make no new series."""
    metrics = PendantMetrics(sim, mode="sim", model="pulse75", robot_url=None)
    before_page = page_series(metrics)
    page = new_page(sim, sim.arm, mode_line="sim", metrics=metrics)
    try:
        at_start = page_series(metrics)
        counts = scraped(metrics)
        for kind in EventKind:
            assert f'pendant_events_total{{kind="{kind.value}"}}' in counts, kind
        page.desk.join(OPERATOR)
        page.desk.join(VIEWER)
        viewer = FakeBrowser(VIEWER).handle
        for i in range(100):
            page.runner.submit(f"Delete obstacle 'box-{i}'", lambda c: None, viewer)
        for port in (1, 2, 3):
            page.runner.submit(f"DO{port} HIGH", lambda c: None, None).result(timeout=WAIT_S)
        freeze(page.runner, None, "Freeze (Esc)").result(timeout=WAIT_S)
        page.runner.record(RECORD_LABEL, None)
        page.runner.record("Program: Run 'pick'", None)
        page.runner.record("Something no page button says", None)
    finally:
        page.stop()
    assert before_page == {}, "no page, no page series"
    assert at_start, "no page series at start"
    assert set(at_start.values()) == {0.0}
    for name in ("Freeze", "Home", "Delete obstacle", "DO", "Program", "other", *PAGE_COMMANDS):
        assert at_start[("pendant_commands_total", name, "sent")] == 0.0, name
        assert at_start[("pendant_command_refusals_total", name, "refused")] == 0.0, name
        assert at_start[("pendant_command_refusals_total", name, "failed")] == 0.0, name
    after = page_series(metrics)
    assert set(after) == set(at_start), f"new series: {set(after) - set(at_start)}"
    counted = {key: value for key, value in after.items() if value}
    assert counted == {
        ("pendant_commands_total", "Delete obstacle", "refused"): 100.0,
        ("pendant_command_refusals_total", "Delete obstacle", "refused"): 100.0,
        ("pendant_commands_total", "DO", "sent"): 3.0,
        ("pendant_commands_total", "Freeze", "sent"): 1.0,
        ("pendant_commands_total", "Record path", "sent"): 1.0,
        ("pendant_commands_total", "Program", "sent"): 1.0,
        ("pendant_commands_total", "other", "sent"): 1.0,
    }
