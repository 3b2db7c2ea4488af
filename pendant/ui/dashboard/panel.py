"""The Dashboard tab: the six motors in a table, plots of angles, currents and temperatures (plots), telemetry
recording to MCAP and CSV (recording), their replay with a ghost arm (replay) and the searchable event log
(events).

The readings are shared: the refresh loop samples the motors once for everybody and renders the table, the
plots' data and the log once per distinct view; each browser's panel only receives the result, and only
while its page shows the tab (kit/tab_watch.py): a browser on another tab is sent the newest table and plots
the moment it opens this one, not every refresh before.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Sequence
from pathlib import Path

import viser

from pendant.controller.types import MotorStatus
from pendant.eventlog import EventLog
from pendant.telemetry import Telemetry
from pendant.ui.dashboard.events import EVENTS_SHOWN, EventLogView, EventsRenderer
from pendant.ui.dashboard.plots import PLOTS, PlotSource, PlotView
from pendant.ui.dashboard.recording import RecordingControls, RecordingListener
from pendant.ui.dashboard.replay import ReplayPanel
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset
from pendant.ui.kit.jobs import PageJobs
from pendant.ui.kit.tab_watch import TabWatch
from pendant.ui.scene.ghost_stage import GhostStage

# (row label, what it means, how a reading shows): one row per quantity, one column per joint, so the table
# is seven narrow columns whatever the panel's width (joints as rows made nine columns, too wide for a phone).
MOTOR_ROWS: tuple[tuple[str, str, Callable[[MotorStatus], str]], ...] = (
    ("Angle °", "Joint angle", lambda m: f"{m.angle:.2f}"),
    ("rpm", "Rotor speed", lambda m: f"{m.rotorVelocity:.1f}"),
    ("I rms A", "RMS current", lambda m: f"{m.rmsCurrent:.2f}"),
    ("U V", "Voltage", lambda m: f"{m.voltage:.1f}"),
    ("Stator °C", "Stator temperature", lambda m: f"{m.statorTemperature:.1f}"),
    ("Servo °C", "Servo temperature", lambda m: f"{m.servoTemperature:.1f}"),
    ("Pos err °", "Position error", lambda m: f"{m.positionError:.3f}"),
)
_CELL = "text-align:right;padding:0 1px"


def render_motor_table(motors: Sequence[MotorStatus] | None) -> str:
    """Per motor (a column each, J1..J6): angle, rotor speed, RMS current, voltage, stator and servo
    temperature, position error (a row each)."""
    if motors is None:
        return '<div style="color:#868e96">No motor readings (controller offline)</div>'
    header = "".join(f'<th style="{_CELL}">J{i + 1}</th>' for i in range(len(motors)))
    rows = [f'<tr><th style="text-align:left;padding:0"></th>{header}</tr>']
    for label, meaning, shown in MOTOR_ROWS:
        tds = "".join(f'<td style="{_CELL}">{shown(m)}</td>' for m in motors)
        rows.append(f'<tr><th style="text-align:left;padding:0" title="{meaning}">{label}</th>{tds}</tr>')
    # A fixed layout shares the panel's width out and never grows past it: a value too long for its column
    # wraps inside the cell rather than widening the panel (which would push Freeze off screen).
    return inset(
        '<table id="motor-table" style="width:100%;table-layout:fixed;border-collapse:collapse;'
        'font-size:0.72em;font-variant-numeric:tabular-nums;overflow-wrap:anywhere">'
        '<colgroup><col style="width:22%"></colgroup>'
        f"{''.join(rows)}</table>"
    )


class DashboardPanel:
    """One browser's dashboard; `show_*` are fed by the refresh loop."""

    def __init__(
        self,
        target: GuiTarget,
        telemetry: Telemetry,
        events: EventLog,
        *,
        may_record: Callable[[viser.ClientHandle | None], str | None],
        on_recording: RecordingListener,
        arm_urdf: Path | None = None,
        jobs: PageJobs | None = None,
        ghosts: GhostStage | None = None,
    ) -> None:
        jobs = jobs if jobs is not None else PageJobs()  # replays and downloads: bounded, off viser's pool
        # The refresh loop's drawings and the tab coming into view (viser's pool) take turns.
        self._drawing = threading.Lock()
        self._table_due: str | None = None  # the newest table and plots, kept while the tab is not shown
        self._plots_due: PlotSource | None = None
        self.on_screen = TabWatch(target, self._tab_shown)
        self.motor_table = target.gui.add_html(render_motor_table(None))
        self.plot_view = PlotView(target)
        with target.gui.add_folder("Recording (MCAP and CSV)"):
            self.recording = RecordingControls(
                target, telemetry, may_record=may_record, on_recording=on_recording, jobs=jobs
            )
        with target.gui.add_folder("Replay"):
            self.replay = ReplayPanel(
                target,
                arm_urdf,
                chosen=self.recording.chosen_file,
                recording_now=lambda: telemetry.mcap.path if telemetry.mcap is not None else None,
                jobs=jobs,
                ghosts=ghosts,
            )
        with target.gui.add_folder("Event log"):
            self.events = EventLogView(target, events, jobs=jobs)
        self._table_html = ""
        # The handles tests and the page's role switch reach for.
        self.plots = self.plot_view.plots
        self.event_log = self.events.log
        self.recording_status = self.recording.recording_status
        self.record_start = self.recording.record_start
        self.record_stop = self.recording.record_stop
        self.download = self.recording.download

    def show_table(self, table_html: str) -> None:
        with self._drawing:
            if self.on_screen.shown:
                self._draw_table(table_html)
                self._table_due = None  # older than this one
            else:
                self._table_due = table_html

    def show_plots(self, source: PlotSource) -> None:
        with self._drawing:
            if self.on_screen.shown:
                self.plot_view.show(source)
                self._plots_due = None  # older than this one
            else:
                self._plots_due = source

    def _tab_shown(self, shown: bool) -> None:
        """The page shows the tab now (or no more): what came meanwhile is drawn at once."""
        with self._drawing:
            if not shown:
                return
            if self._table_due is not None:
                self._draw_table(self._table_due)
            if self._plots_due is not None:
                self.plot_view.show(self._plots_due)
            self._table_due = self._plots_due = None

    def _draw_table(self, table_html: str) -> None:
        if table_html != self._table_html:
            self.motor_table.content = table_html
            self._table_html = table_html

    def show_events(self, render: EventsRenderer) -> None:
        self.events.show(render)

    def show_recording(self, *, locked: bool) -> None:
        self.recording.show(locked=locked)

    def close(self) -> None:
        """The browser left: a replay playing stops."""
        self.replay.close()


__all__ = ["EVENTS_SHOWN", "PLOTS", "DashboardPanel", "render_motor_table"]
