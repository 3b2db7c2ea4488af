"""The Dashboard tab: the six motors in a table, plots of angles, currents and temperatures (plots), telemetry
recording to MCAP and CSV (recording), their replay with a ghost arm (replay) and the searchable event log
(events).

The readings are shared: the refresh loop samples the motors once for everybody and renders the table, the
plots' data and the log once per distinct view; each browser's panel only receives the result.
"""

from __future__ import annotations

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
    ) -> None:
        self.motor_table = target.gui.add_html(render_motor_table(None))
        self.plot_view = PlotView(target)
        with target.gui.add_folder("Recording (MCAP and CSV)"):
            self.recording = RecordingControls(
                target, telemetry, may_record=may_record, on_recording=on_recording
            )
        with target.gui.add_folder("Replay"):
            self.replay = ReplayPanel(
                target,
                arm_urdf,
                chosen=self.recording.chosen_file,
                recording_now=lambda: telemetry.mcap.path if telemetry.mcap is not None else None,
            )
        with target.gui.add_folder("Event log"):
            self.events = EventLogView(target, events)
        self._table_html = ""
        # The handles tests and the page's role switch reach for.
        self.plots = self.plot_view.plots
        self.event_log = self.events.log
        self.recording_status = self.recording.recording_status
        self.record_start = self.recording.record_start
        self.record_stop = self.recording.record_stop
        self.download = self.recording.download

    def show_table(self, table_html: str) -> None:
        if table_html != self._table_html:
            self.motor_table.content = table_html
            self._table_html = table_html

    def show_plots(self, source: PlotSource) -> None:
        self.plot_view.show(source)

    def show_events(self, render: EventsRenderer) -> None:
        self.events.show(render)

    def show_recording(self, *, locked: bool) -> None:
        self.recording.show(locked=locked)

    def close(self) -> None:
        """The browser left: a replay playing stops."""
        self.replay.close()


__all__ = ["EVENTS_SHOWN", "PLOTS", "DashboardPanel", "render_motor_table"]
