"""The Dashboard's event log: the newest events of the whole stored log (not only this run's), filtered by
kind, by who and by text, with runs of state changes folded into one line so that a looping program does not
push the commands and failures out of sight; the filtered log downloads as CSV."""

from __future__ import annotations

import csv
import datetime as dt
import html
import io
from collections.abc import Callable, Sequence

import viser

from pendant.eventlog import EventKind, EventLog
from pendant.eventquery import EventQuery, StoredEvent
from pendant.ui.kit.download import send_bytes
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.jobs import PageJobs

EVENTS_SHOWN = 40
EXPORT_MAX_ROWS = 100_000
FILTER_MAX_CHARS = 200
EVENT_COLOURS = {
    EventKind.STATE.value: "#1971c2",
    EventKind.ERROR.value: "#e03131",
    EventKind.COMMAND.value: "#237032",
    EventKind.REFUSED.value: "#e8590c",
    EventKind.CONTROL.value: "#9c36b5",
}
KIND_FILTERS: dict[str, tuple[str, ...]] = {
    "Everything": (),
    "Failures and refusals": (EventKind.ERROR.value, EventKind.REFUSED.value),
    "Commands": (EventKind.COMMAND.value,),
    "Control hand-overs": (EventKind.CONTROL.value,),
    "State changes": (EventKind.STATE.value,),
}
EventsRenderer = Callable[[EventQuery], str]  # the refresh loop's, shared by every browser with that query


def _when(epoch: float) -> str:
    moment = dt.datetime.fromtimestamp(epoch)
    today = dt.datetime.now().date()
    return moment.strftime("%H:%M:%S" if moment.date() == today else "%d %b %H:%M:%S")


def render_events(rows: Sequence[StoredEvent]) -> str:
    """Newest first: time, kind (×N when state changes were folded), who, what."""
    if not rows:
        return '<div id="event-log" style="color:#868e96;font-size:0.85em">No events</div>'
    lines = []
    for row in rows:
        colour = EVENT_COLOURS.get(row.kind, "#495057")
        folded = f" ×{row.count}" if row.count > 1 else ""
        since = f" since {_when(row.first_time)}" if row.count > 1 and row.first_time is not None else ""
        lines.append(
            f'<div><span style="color:#868e96">{_when(row.time)}</span> '
            f'<b style="color:{colour}">{row.kind}{folded}</b>{since} '
            f"<i>{html.escape(row.source)}</i>: {html.escape(row.message)}</div>"
        )
    return (
        '<div id="event-log" tabindex="0" role="log" aria-label="Event log" '
        'style="font-size:0.78em;line-height:1.35;max-height:360px;overflow-y:auto">'
        f"{''.join(lines)}</div>"
    )


def events_csv(rows: Sequence[StoredEvent]) -> bytes:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["id", "time_utc", "kind", "who", "what"])
    for row in rows:
        when = dt.datetime.fromtimestamp(row.time, dt.UTC).isoformat(timespec="milliseconds")
        writer.writerow([row.id, when, row.kind, row.source, row.message])
    return out.getvalue().encode()


class EventLogView:
    """One browser's view of the log: its filter, the lines it shows, its download."""

    def __init__(self, target: GuiTarget, events: EventLog, *, jobs: PageJobs | None = None) -> None:
        self._target = target
        self._jobs = jobs if jobs is not None else PageJobs()
        self._events = events
        self.kind = target.gui.add_dropdown("Show", tuple(KIND_FILTERS), initial_value="Everything")
        self.who = target.gui.add_text("Who", "", hint="Part of the sender: 'browser #2', an address")
        self.text = target.gui.add_text("Text", "", hint="Part of the message, e.g. 'failed'")
        self.fold = target.gui.add_checkbox("Fold state changes", True)
        self.log = target.gui.add_html(render_events([]))
        self.download = target.gui.add_button("Download log (CSV)", icon=viser.Icon.DOWNLOAD)
        for handle in (self.kind, self.who, self.text, self.fold):
            handle.on_update(lambda _: self.refresh())
        self.download.on_click(  # the browser's one job at a time (kit/jobs.py), off viser's callback pool
            lambda event: self._jobs.start("Download log", event.client, lambda: self.send_csv(event.client))
        )
        self._html = ""

    def query(self, limit: int = EVENTS_SHOWN) -> EventQuery:
        return EventQuery(
            kinds=KIND_FILTERS[self.kind.value],
            who=self.who.value.strip()[:FILTER_MAX_CHARS],
            text=self.text.value.strip()[:FILTER_MAX_CHARS],
            limit=limit,
            fold=self.fold.value,
        )

    def show(self, render: EventsRenderer) -> None:
        """Something new was logged: the refresh loop's rendering for this view's query."""
        self._set(render(self.query()))

    def refresh(self) -> None:
        """The filter changed: search now (a callback thread, not the refresh loop)."""
        self._set(render_events(self._events.search(self.query())))

    def _set(self, content: str) -> None:
        if content != self._html:
            self.log.content = content
            self._html = content

    def send_csv(self, client: viser.ClientHandle | None) -> bytes:
        """Every event the filter lets through (not folded), up to EXPORT_MAX_ROWS, newest first."""
        query = EventQuery(
            kinds=KIND_FILTERS[self.kind.value],
            who=self.who.value.strip()[:FILTER_MAX_CHARS],
            text=self.text.value.strip()[:FILTER_MAX_CHARS],
            limit=EXPORT_MAX_ROWS,
        )
        if self._events.store is not None:
            self._events.store.flush(timeout=1.0)
        content = events_csv(self._events.search(query, cap=EXPORT_MAX_ROWS))
        name = f"pendant-events-{dt.datetime.now():%Y%m%d-%H%M%S}.csv"
        if client is None:
            self._target.send_file_download(name, content, save_immediately=True)
        else:
            send_bytes(client, name, content)
        return content
