"""The Dashboard tab: the six motors in a table, 60 s plots of angles, currents and temperatures (uPlot),
the event log, and telemetry recording to CSV.

The readings are shared: the refresh loop samples the motors once for everybody and renders the table and the
log once (`render_*`); each browser's panel only receives the result.
"""

from __future__ import annotations

import datetime as dt
import html
from collections.abc import Callable, Sequence

import numpy as np
import viser
import viser.uplot as uplot

from pendant.controller.types import MotorStatus
from pendant.eventlog import Event, EventKind
from pendant.telemetry import HISTORY_S, Telemetry
from pendant.telemetry.history import HistoryWindow
from pendant.ui.gui_target import GuiTarget
from pendant.ui.html import inset

EVENTS_SHOWN = 14
PLOT_HEIGHT_PX = 170
JOINT_COLOURS = ("#e03131", "#2f9e44", "#1971c2", "#f08c00", "#9c36b5", "#0c8599")
EVENT_COLOURS = {
    EventKind.STATE: "#1971c2",
    EventKind.ERROR: "#e03131",
    EventKind.COMMAND: "#2b8a3e",
    EventKind.REFUSED: "#e8590c",
    EventKind.CONTROL: "#9c36b5",
}
PLOTS = (
    ("angle", "Joint angles (°)"),
    ("current", "RMS currents (A)"),
    ("stator", "Stator temperatures (°C)"),
)

PlotData = dict[str, tuple[np.ndarray, ...]]


def render_motor_table(motors: Sequence[MotorStatus] | None) -> str:
    """Per motor: angle, rotor speed, RMS current, voltage, stator and servo temperature, position error."""
    if motors is None:
        return '<div style="color:#868e96">No motor readings (controller offline)</div>'
    header = "".join(
        f'<th style="text-align:right;padding:0 2px;white-space:nowrap">{h}</th>'
        for h in ("", "Angle °", "rpm", "I rms A", "U V", "Stator °C", "Servo °C", "Pos err °")
    )
    rows = []
    for i, m in enumerate(motors):
        cells = (
            f"{m.angle:.2f}",
            f"{m.rotorVelocity:.1f}",
            f"{m.rmsCurrent:.2f}",
            f"{m.voltage:.1f}",
            f"{m.statorTemperature:.1f}",
            f"{m.servoTemperature:.1f}",
            f"{m.positionError:.3f}",
        )
        tds = "".join(f'<td style="text-align:right;padding:0 2px">{c}</td>' for c in cells)
        rows.append(f"<tr><td><b>J{i + 1}</b></td>{tds}</tr>")
    # Nine columns are wider than the panel on a narrow screen: scroll sideways rather than cut them off.
    return inset(
        '<div style="overflow-x:auto"><table id="motor-table" '
        'style="width:100%;font-size:0.72em;font-family:monospace;border-collapse:collapse">'
        f"<tr>{header}</tr>{''.join(rows)}</table></div>"
    )


def render_events(events: Sequence[Event]) -> str:
    """The newest events first: time, who, what."""
    if not events:
        return '<div style="color:#868e96;font-size:0.85em">No events yet</div>'
    rows = []
    for event in reversed(events):
        when = dt.datetime.fromtimestamp(event.wall_time).strftime("%H:%M:%S")
        colour = EVENT_COLOURS.get(event.kind, "#495057")
        rows.append(
            f'<div><span style="color:#868e96">{when}</span> '
            f'<b style="color:{colour}">{event.kind.value}</b> '
            f"<i>{html.escape(event.source)}</i>: {html.escape(event.message)}</div>"
        )
    return f'<div id="event-log" style="font-size:0.78em;line-height:1.35">{"".join(rows)}</div>'


def plot_data(window: HistoryWindow, every: int = 1) -> PlotData:
    """The plots. uPlot data (x = seconds ago, then a series per joint), thinned to every n-th sample."""
    t = window.t[::-1][::every][::-1]  # keep the newest sample whatever the stride

    def series(values: np.ndarray) -> tuple[np.ndarray, ...]:
        thinned = values[::-1][::every][::-1]
        return (t, *(thinned[:, j] for j in range(thinned.shape[1])))

    return {
        "angle": series(window.angle_deg),
        "current": series(window.current_a),
        "stator": series(window.stator_c),
    }


def _empty_plot_data() -> tuple[np.ndarray, ...]:
    return tuple(np.zeros(1) for _ in range(7))


class DashboardPanel:
    """One browser's dashboard; `show_*` are fed by the refresh loop."""

    def __init__(
        self,
        target: GuiTarget,
        telemetry: Telemetry,
        *,
        may_record: Callable[[viser.ClientHandle | None], str | None],
        on_recording: Callable[[viser.ClientHandle | None, str], None],
    ) -> None:
        self._target = target
        self._telemetry = telemetry
        self._may_record = may_record
        self._on_recording = on_recording
        self.motor_table = target.gui.add_html(render_motor_table(None))
        self.plots: dict[str, viser.GuiUplotHandle] = {}
        for key, title in PLOTS:
            self.plots[key] = target.gui.add_uplot(
                data=_empty_plot_data(),
                series=(
                    uplot.Series(label="s"),
                    *(uplot.Series(label=f"J{j + 1}", stroke=JOINT_COLOURS[j], width=1.5) for j in range(6)),
                ),
                title=title,
                scales={"x": uplot.Scale(time=False, range=(-HISTORY_S, 0.0))},
                legend=uplot.Legend(show=True),
                height=PLOT_HEIGHT_PX,
            )
        with target.gui.add_folder("Recording (CSV)"):
            self.recording_status = target.gui.add_markdown("Not recording.")
            self.record_start = target.gui.add_button("Start recording", icon=viser.Icon.PLAYER_RECORD)
            self.record_stop = target.gui.add_button(
                "Stop recording", icon=viser.Icon.PLAYER_STOP, disabled=True
            )
            self.download = target.gui.add_button("Download CSV", icon=viser.Icon.DOWNLOAD, disabled=True)
        with target.gui.add_folder("Event log"):
            self.event_log = target.gui.add_html(render_events([]))
        self.record_start.on_click(lambda event: self.start_recording(event.client))
        self.record_stop.on_click(lambda event: self.stop_recording(event.client))
        self.download.on_click(lambda event: self.send_csv(event.client))
        self._table_html = ""
        self._events_html = ""
        self._recording_text = ""

    # --- fed by the refresh loop --------------------------------------------------------------------
    def show_table(self, table_html: str) -> None:
        if table_html != self._table_html:
            self.motor_table.content = table_html
            self._table_html = table_html

    def show_plots(self, data: PlotData) -> None:
        for key, handle in self.plots.items():
            if len(data[key][0]) >= 2:
                handle.data = data[key]

    def show_events(self, events_html: str) -> None:
        if events_html != self._events_html:
            self.event_log.content = events_html
            self._events_html = events_html

    def show_recording(self, *, locked: bool) -> None:
        recorder = self._telemetry.recorder
        if recorder.recording:
            text = f"**Recording** · {recorder.row_count} samples"
        elif recorder.row_count:
            text = f"Stopped · {recorder.row_count} samples ready to download"
        else:
            text = "Not recording."
        if text != self._recording_text:
            self.recording_status.content = text
            self._recording_text = text
        for handle, disabled in (
            (self.record_start, locked or recorder.recording),
            (self.record_stop, locked or not recorder.recording),
            (self.download, recorder.row_count == 0),
        ):
            if handle.disabled != disabled:  # each assignment is a message to the browser
                handle.disabled = disabled

    # --- buttons ------------------------------------------------------------------------------------
    def start_recording(self, client: viser.ClientHandle | None) -> bool:
        if self._refused(client, "Start recording"):
            return False
        self._telemetry.start_recording()
        self._on_recording(client, "Recording started")
        return True

    def stop_recording(self, client: viser.ClientHandle | None) -> bool:
        if self._refused(client, "Stop recording"):
            return False
        rows = self._telemetry.stop_recording()
        self._on_recording(client, f"Recording stopped: {rows} samples")
        return True

    def send_csv(self, client: viser.ClientHandle | None) -> bytes:
        content = self._telemetry.recorder.to_csv()
        name = f"pendant-telemetry-{dt.datetime.now():%Y%m%d-%H%M%S}.csv"
        (client if client is not None else self._target).send_file_download(
            name, content, save_immediately=True
        )
        return content

    def _refused(self, client: viser.ClientHandle | None, label: str) -> bool:
        reason = self._may_record(client)
        if reason is not None and client is not None:
            client.add_notification(
                title=f"{label} refused", body=reason, color="red", auto_close_seconds=8.0
            )
        return reason is not None
