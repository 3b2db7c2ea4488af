"""The Dashboard as people read it: plots with units and current values, one joint or all, any window up to
an hour, paused; the event log searched and folded over the stored history, downloadable; recordings kept
and downloadable as MCAP. Headless: the pendant's own refresh step and the tab's controls as a browser uses
them."""

from __future__ import annotations

import csv
import io
import re
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import viser
from mcap.reader import make_reader

from pendant.controller import MotionParams, Pose
from pendant.eventlog import EventKind, EventLog
from pendant.monitoring import EventStore
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.dashboard.plots import MAX_POINTS, PLOT_HEIGHT_PX, UNITS
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.pages import headless_session, new_page
from tests.support.waiting import SAFETY_NET_S, wait_until

SAMPLE_PERIOD_S = 0.1
MOVE = Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0])
READABLE_HEIGHT_PX = 200
JOB_TIMEOUT_S = SAFETY_NET_S  # downloads run on a job thread (kit/jobs.py)


@pytest.fixture
def pendant_ui(sim: SimController, clock: FakeClock) -> Iterator[PendantUI]:
    """The page with its telemetry on the simulator's fake clock (an hour of history in a moment)."""
    page = new_page(sim, sim.arm, clock=clock.now)
    page.desk.join(OPERATOR)
    page.desk.join(VIEWER)
    page.refresh()
    yield page
    page.stop()


def run_for(pendant_ui: PendantUI, clock: FakeClock, seconds: float) -> None:
    """The refresh loop's motor sampling for `seconds` (drawing only at the end)."""
    for _ in range(round(seconds / SAMPLE_PERIOD_S)):
        clock.advance(SAMPLE_PERIOD_S)
        pendant_ui.refresh_dashboard(table=False, plots=False)
    pendant_ui.refresh_dashboard(sample=False)


def legend(plot: viser.GuiUplotHandle) -> list[str]:
    return [str(s["label"]) for s in plot.series[1:]]


def shown(plot: viser.GuiUplotHandle) -> list[bool]:
    return [bool(s.get("show", True)) for s in plot.series[1:]]


def test_plots_show_units_and_current_values(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    sim.set_pose(MOVE, MotionParams(speed=30.0))
    run_for(pendant_ui, clock, 2.0)
    motors = pendant_ui.telemetry.latest
    assert motors is not None
    for key, plot in ui.dashboard.plots.items():
        unit, _ = UNITS[key]
        assert plot.height is not None and plot.axes is not None and plot.legend is not None
        assert plot.height >= READABLE_HEIGHT_PX and PLOT_HEIGHT_PX >= READABLE_HEIGHT_PX
        assert plot.axes[1]["label"] == unit and plot.axes[0]["label"] == "s ago"
        assert plot.legend["live"] is False, "uPlot's live legend shows '--' until hovered"
        labels = legend(plot)
        assert all("--" not in label and label.endswith(unit) for label in labels)
    values = [float(label.split()[1]) for label in legend(ui.dashboard.plots["angle"])]  # "J1 12.3 °"
    assert all(re.match(r"J\d \S+ °", label) for label in legend(ui.dashboard.plots["angle"]))
    np.testing.assert_allclose(values, [m.angle for m in motors], atol=0.05)


def test_one_joint_or_all(ui: ClientSession, pendant_ui: PendantUI, clock: FakeClock) -> None:
    operator = FakeBrowser(OPERATOR)
    run_for(pendant_ui, clock, 1.0)
    fire(ui.dashboard.plot_view.joint, operator, "J3")
    assert all(
        shown(plot) == [False, False, True, False, False, False] for plot in ui.dashboard.plots.values()
    )
    fire(ui.dashboard.plot_view.joint, operator, "All joints")
    assert all(all(shown(plot)) for plot in ui.dashboard.plots.values())


def test_longer_windows_reach_back_an_hour_and_pause_holds_the_picture(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    viewer = FakeBrowser(VIEWER)
    sim.set_pose(MOVE, MotionParams(speed=5.0))
    run_for(pendant_ui, clock, 240.0)
    angle = ui.dashboard.plots["angle"]
    assert angle.data[0][0] >= -60.0, "the last minute by default"

    fire(ui.dashboard.plot_view.window, viewer, "Last 5 minutes")
    t = angle.data[0]
    assert angle.axes is not None and angle.scales is not None
    assert angle.axes[0]["label"] == "min ago" and angle.scales["x"]["range"] == (-5.0, 0.0)
    assert t[0] <= -3.9 and t[-1] == 0.0, "four minutes of history, in minutes"
    assert len(t) <= MAX_POINTS

    fire(ui.dashboard.plot_view.paused, viewer, True)
    held = [np.array(a) for a in angle.data]
    run_for(pendant_ui, clock, 5.0)
    assert all(np.array_equal(a, b) for a, b in zip(held, angle.data, strict=True)), "paused: unchanged"
    fire(ui.dashboard.plot_view.window, viewer, "Last minute")  # zoom in on the paused picture's time
    assert angle.data[0][0] >= -60.0 and angle.axes[0]["label"] == "s ago"
    fire(ui.dashboard.plot_view.paused, viewer, False)
    run_for(pendant_ui, clock, 1.0)
    latest = pendant_ui.telemetry.latest
    assert latest is not None and angle.data[1][-1] == latest[0].angle


def lines(ui: ClientSession) -> list[str]:
    return [
        re.sub(r"<.*?>", "", line)
        for line in re.findall(r"<div><span.*?</div>", ui.dashboard.event_log.content)
    ]


def test_a_looping_program_does_not_drown_commands_and_filters_find_them(
    ui: ClientSession, pendant_ui: PendantUI
) -> None:
    operator = FakeBrowser(OPERATOR)
    events = pendant_ui.events
    events.record(EventKind.COMMAND, "browser #1 (10.0.0.7)", "Run pick (loop until Stop)")
    for i in range(300):
        events.record(EventKind.STATE, "controller", "IDLE → RUNNING" if i % 2 == 0 else "RUNNING → IDLE")
    events.record(EventKind.ERROR, "program", "Step 2 (Move J to P2 @ 50%) failed: Collision detected")
    events.record(EventKind.REFUSED, "browser #2 (10.0.0.9)", "Home: browser #2 is a viewer")
    pendant_ui.refresh_dashboard()
    shown_lines = lines(ui)[:4]  # below them: the page's start (control taken, controller IDLE)
    assert "state ×300" in shown_lines[2] and "RUNNING → IDLE" in shown_lines[2]
    assert "Run pick" in shown_lines[3]

    view = ui.dashboard.events
    fire(view.kind, operator, "Failures and refusals")
    assert [line.split(": ", 1)[1] for line in lines(ui)] == [
        "Home: browser #2 is a viewer",
        "Step 2 (Move J to P2 @ 50%) failed: Collision detected",
    ]
    fire(view.kind, operator, "Everything")
    fire(view.who, operator, "10.0.0.7")
    assert len(lines(ui)) == 1 and "Run pick" in lines(ui)[0]
    fire(view.who, operator, "")
    fire(view.text, operator, "collision")
    assert len(lines(ui)) == 1 and "Collision detected" in lines(ui)[0]
    fire(view.text, operator, "")
    fire(view.fold, operator, False)
    assert len(lines(ui)) == 40 and all("state" in line for line in lines(ui)[2:])

    fire(view.kind, operator, "Commands")
    fire(view.download, operator)
    wait_until(lambda: bool(operator.downloads), JOB_TIMEOUT_S, "the download")  # a job (kit/jobs.py)
    ((name, content),) = operator.downloads
    rows = list(csv.reader(io.StringIO(content.decode())))
    assert name.startswith("pendant-events-") and name.endswith(".csv")
    assert rows[0] == ["id", "time_utc", "kind", "who", "what"]
    assert rows[1][2:] == ["command", "browser #1 (10.0.0.7)", "Run pick (loop until Stop)"]


def test_the_dashboard_shows_the_stored_log_of_earlier_runs(sim: SimController, tmp_path: Path) -> None:
    store = EventStore(tmp_path)
    first = EventLog(store=store)
    first.record(EventKind.COMMAND, "browser #4 (10.0.0.3)", "Move J")
    first.record(EventKind.ERROR, "controller", "Collision detected")
    store.close()

    store = EventStore(tmp_path)  # the pendant started again
    page = new_page(sim, sim.arm, mode_line="sim", events=EventLog(store=store))
    try:
        session = headless_session(page)
        page.refresh_dashboard()
        assert [line.split(": ", 1)[1] for line in lines(session)] == ["Collision detected", "Move J"]
        page.events.record(EventKind.CONTROL, "browser #5", "took control")
        store.flush()
        page.refresh_dashboard()
        assert "took control" in lines(session)[0]
    finally:
        page.stop()
        store.close()


def test_recordings_are_listed_and_download_as_mcap(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    operator = FakeBrowser(OPERATOR)
    controls = ui.dashboard.recording
    assert controls.saved.options == ("(none yet)",)
    fire(controls.record_start, operator)
    sim.set_pose(MOVE, MotionParams(speed=30.0))
    run_for(pendant_ui, clock, 1.0)
    fire(controls.record_stop, operator)
    pendant_ui.refresh_dashboard()
    (label,) = controls.saved.options
    stem = pendant_ui.telemetry.last_stem
    assert stem is not None and label.startswith(stem.removeprefix("pendant-"))
    fire(controls.download_mcap, operator, label)
    wait_until(lambda: bool(operator.downloads), JOB_TIMEOUT_S, "the download")
    ((name, content),) = operator.downloads
    assert name.endswith(".mcap")
    reader = make_reader(io.BytesIO(content))
    topics = [channel.topic for _, channel, _ in reader.iter_messages()]
    assert topics.count("/joints") == 10 and "/events" in topics  # "Recording started" is in it
