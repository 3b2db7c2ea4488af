"""The Dashboard tab headless: the motor table, the live plots, the event log and CSV recording, fed by the
pendant's own refresh step and driven by the tab's buttons as a browser would click them."""

from __future__ import annotations

import csv
import io
import re

import numpy as np
import pytest

from pendant.controller import MotionParams
from pendant.eventlog import EventKind
from pendant.sim import FakeClock, SimController
from pendant.telemetry import CSV_FIELDS, csv_header
from pendant.ui.app import PendantUI
from pendant.ui.dashboard.panel import EVENTS_SHOWN, PLOTS
from pendant.ui.page.session import ClientSession
from tests.support.dashboard import MOVE, sample
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.waiting import wait_until

VALUE_TOL = 1e-9
FUTURE_TIMEOUT_S = 60.0  # a safety net: a thread starved of CPU (nice 19, a loaded machine) may take seconds
TABLE_ROWS = ("Angle °", "rpm", "I rms A", "U V", "Stator °C", "Servo °C", "Pos err °")


@pytest.fixture
def operator() -> FakeBrowser:
    return FakeBrowser(OPERATOR)


def shown_events(ui: ClientSession) -> list[tuple[str, str]]:
    """(who, what) of each line of the event log, top to bottom."""
    return re.findall(r"<i>(.*?)</i>: (.*?)</div>", ui.dashboard.event_log.content)


def test_the_motor_table_shows_six_motors_with_every_field(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    assert "No motor readings" in ui.dashboard.motor_table.content
    pendant_ui.refresh_dashboard()
    table = ui.dashboard.motor_table.content
    header, *rows = re.findall(r"<tr>(.*?)</tr>", table)
    # Joints as columns, a quantity a row: seven narrow columns fit a phone's panel.
    assert [re.sub(r"<.*?>", "", c) for c in re.findall(r"<th.*?</th>", header)] == [
        "",
        *(f"J{j + 1}" for j in range(6)),
    ]
    assert [re.sub(r"<.*?>", "", re.findall(r"<th.*?</th>", row)[0]) for row in rows] == list(TABLE_ROWS)
    cells = {
        label: [float(re.sub(r"<.*?>", "", c)) for c in re.findall(r"<td.*?</td>", row)]
        for label, row in zip(TABLE_ROWS, rows, strict=True)
    }
    motors = sim.get_motors()
    assert all(len(values) == 6 for values in cells.values())
    assert cells["Angle °"] == pytest.approx([m.angle for m in motors], abs=0.005)  # shown to 0.01°
    assert cells["I rms A"] == pytest.approx([m.rmsCurrent for m in motors], abs=0.005)  # to 0.01 A


def test_the_plots_fill_with_the_samples(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    assert all(len(plot.data[0]) == 1 for plot in ui.dashboard.plots.values()), "empty until sampled"
    sim.set_pose(MOVE, MotionParams(speed=30.0))
    readings = sample(pendant_ui, clock, 10)
    latest = readings[-1]
    expected_newest = {
        "angle": [m.angle for m in latest],
        "current": [m.rmsCurrent for m in latest],
        "stator": [m.statorTemperature for m in latest],
    }
    assert set(ui.dashboard.plots) == {key for key, _ in PLOTS}
    for key, plot in ui.dashboard.plots.items():
        t, *series = plot.data
        assert len(series) == 6 and len(t) >= 2
        assert t[-1] == 0.0 and np.all(np.diff(t) > 0), "seconds ago, oldest first"
        np.testing.assert_allclose([s[-1] for s in series], expected_newest[key], atol=VALUE_TOL)
    angle_j1 = ui.dashboard.plots["angle"].data[1]
    assert angle_j1[-1] > angle_j1[0] + 1.0, "the plot shows J1 turning"


def test_the_event_log_lists_the_newest_first_with_who_did_it(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser
) -> None:
    for label in ("Home", "Relax"):
        fire(ui.robot_buttons[label], operator)
    pendant_ui.refresh_dashboard()
    shown = shown_events(ui)
    assert shown[:2] == [("browser #1", "Relax"), ("browser #1", "Home")]
    assert [what for _, what in shown] == [e.message for e in reversed(pendant_ui.events.recent())]


def test_the_event_log_shows_only_the_latest_events(ui: ClientSession, pendant_ui: PendantUI) -> None:
    for i in range(EVENTS_SHOWN + 5):
        pendant_ui.events.record(EventKind.COMMAND, "API 127.0.0.1", f"PUT /freeze #{i}")
    pendant_ui.refresh_dashboard()
    shown = [what for _, what in shown_events(ui)]
    assert len(shown) == EVENTS_SHOWN
    assert shown[0] == f"PUT /freeze #{EVENTS_SHOWN + 4}" and shown[-1] == "PUT /freeze #5"


def test_recording_start_stop_and_download_give_a_csv_of_the_samples(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    dashboard = ui.dashboard
    assert dashboard.download.disabled and dashboard.record_stop.disabled
    sample(pendant_ui, clock, 3)  # before the start: not recorded
    fire(dashboard.record_start, operator)
    sim.set_pose(MOVE, MotionParams(speed=30.0))
    recorded = sample(pendant_ui, clock, 15)
    assert "**Recording** · 15 samples" in dashboard.recording_status.content
    assert dashboard.record_start.disabled and not dashboard.record_stop.disabled
    fire(dashboard.record_stop, operator)
    sample(pendant_ui, clock, 3)  # after the stop: not recorded
    assert dashboard.recording_status.content == "Stopped · 15 samples ready to download"
    assert not dashboard.download.disabled

    fire(dashboard.download, operator)
    wait_until(lambda: bool(operator.downloads), FUTURE_TIMEOUT_S, "the download")  # a job (kit/jobs.py)
    ((name, content),) = operator.downloads
    assert name.startswith("pendant-telemetry-") and name.endswith(".csv")
    rows = list(csv.reader(io.StringIO(content.decode())))
    assert rows[0] == csv_header()
    assert len(rows) == 1 + len(recorded)
    times = [float(row[0]) for row in rows[1:]]
    assert times[0] >= 0.0 and np.all(np.diff(times) >= 0.0)
    for row, motors in zip(rows[1:], recorded, strict=True):
        expected = [getattr(m, f) for m in motors for f in CSV_FIELDS]
        np.testing.assert_allclose([float(v) for v in row[1:]], expected, rtol=0, atol=VALUE_TOL)
    commands = [(e.source, e.message) for e in pendant_ui.events.recent() if e.kind is EventKind.COMMAND]
    assert ("browser #1", "Recording started") in commands
    assert ("browser #1", "Recording stopped: 15 samples") in commands
