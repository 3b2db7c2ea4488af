"""What every dashboard shares, made once a refresh for all of them: the motors read once into the shared
history, the motor table, the plots once per window length the browsers show, and the event log once per
distinct filter (only when the log changed, or a browser just came)."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Protocol

from pendant.eventlog import EventLog
from pendant.eventquery import EventQuery
from pendant.telemetry import ArmState, Telemetry
from pendant.ui.dashboard.events import EventsRenderer, render_events
from pendant.ui.dashboard.panel import render_motor_table
from pendant.ui.dashboard.plots import PlotData, PlotSource, plot_data
from pendant.ui.kit.snapshot import Snapshot


class SharedDashboard(Protocol):
    """A browser's dashboard, as the feed fills it (a client session)."""

    def show_dashboard(
        self, *, table_html: str | None, plots: PlotSource | None, events: EventsRenderer | None
    ) -> None: ...


class DashboardFeed:
    def __init__(self, telemetry: Telemetry, events: EventLog) -> None:
        self.telemetry = telemetry
        self.events = events
        self._events_seq = -1  # the log as the dashboards last showed it

    def show_log_again(self) -> None:
        """A browser came: show it the log at the next push, changed or not."""
        self._events_seq = -1

    def push(
        self,
        latest: Snapshot,
        dashboards: Iterable[SharedDashboard],
        *,
        sample: bool = True,
        table: bool = True,
        plots: bool = True,
        arm: Callable[[], ArmState] | None = None,
    ) -> None:
        """Read the motors once (with what `arm` says besides them: pose, IO, status, cell, program step;
        by default `latest`'s pose, IO and status) and push the shared renderings."""
        if sample:
            status = latest.motion_status.value if latest.motion_status is not None else None
            state = (
                arm() if arm is not None else ArmState(latest.position, latest.outputs, latest.inputs, status)
            )
            self.telemetry.sample(state)
        table_html = render_motor_table(self.telemetry.latest) if table else None
        plot_cache: dict[float, PlotData] = {}  # one per window length the browsers show

        def plots_for(window_s: float) -> PlotData:
            if window_s not in plot_cache:
                plot_cache[window_s] = plot_data(self.telemetry.window(window_s), window_s)
            return plot_cache[window_s]

        events_cache: dict[EventQuery, str] = {}  # one search per distinct filter

        def events_for(query: EventQuery) -> str:
            if query not in events_cache:
                events_cache[query] = render_events(self.events.search(query))
            return events_cache[query]

        show_events = table and self.events.searchable_seq != self._events_seq
        if show_events:
            self._events_seq = self.events.searchable_seq
        for dashboard in dashboards:
            dashboard.show_dashboard(
                table_html=table_html,
                plots=plots_for if plots else None,
                events=events_for if show_events else None,
            )
