"""The Jog tab's teach row, right under the jog pad: Record, Record + close gripper, Record + open gripper and
Run, so a program is taught where the arm is jogged (before, Record and Run were on the Program tab: a
pick-and-place took 44 actions and 10 tab switches). The Record button names the last waypoint taught.

Its buttons are the page's own markup (one row of 48 px touch targets, which viser's full-width buttons
would stack into four rows); each click is the click of a hidden viser button (client_page.js sends it, as
for the jog pad), so the server gates it as any other button.
"""

from __future__ import annotations

import html
from collections.abc import Callable

import viser

from pendant.program import Change, GripperAction, ProgramWorkspace, RunState
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset
from pendant.ui.kit.view_only import VIEW_ONLY_HINT

RecordAction = Callable[[viser.ClientHandle | None, GripperAction | None], object]
RunAction = Callable[[viser.ClientHandle | None], object]

TEACH_BUTTON_STYLE = (
    "min-height:48px;min-width:44px;padding:2px 4px;line-height:1.15;font-size:0.9em;font-weight:600;"
    "border-radius:6px;cursor:pointer;border:1px solid #adb5bd;background:#f1f3f5;color:#212529"
)
RECORD_STYLE = "background:#c92a2a;border-color:#a51111;color:#fff"
RUN_STYLE = "background:#237032;border-color:#1b5727;color:#fff"
SUB_STYLE = "display:block;font-size:0.8em;font-weight:normal"


class TeachBar:
    """`record(client, gripper)` records a waypoint (then a gripper step when `gripper` is given);
    `run(client)` runs the program. Both are the Program tab's own (the session wires them)."""

    def __init__(
        self,
        target: GuiTarget,
        programs: ProgramWorkspace,
        record: RecordAction,
        run: RunAction,
        *,
        order: float | None = None,
    ) -> None:
        gui = target.gui
        self._programs = programs
        self.record = gui.add_button("Record", visible=False)
        self.record_close = gui.add_button("Record + close gripper", visible=False)
        self.record_open = gui.add_button("Record + open gripper", visible=False)
        self.run = gui.add_button("Run", visible=False)
        self.record.on_click(lambda e: record(e.client, None))
        self.record_close.on_click(lambda e: record(e.client, GripperAction.CLOSE))
        self.record_open.on_click(lambda e: record(e.client, GripperAction.OPEN))
        self.run.on_click(lambda e: run(e.client))
        self.row = gui.add_html("", order=order)
        self._locked = False
        self._listener = self._on_change
        programs.on_change(self._listener)
        self.redraw()

    @property
    def controls(self) -> tuple[viser.GuiButtonHandle, ...]:
        return (self.record, self.record_close, self.record_open, self.run)

    def set_locked(self, locked: bool) -> None:
        if locked != self._locked:
            self._locked = locked
            self.redraw()

    def close(self) -> None:
        self._programs.remove_listener(self._listener)

    def last_waypoint(self) -> str | None:
        waypoints = self._programs.program.waypoints
        return waypoints[-1].name if waypoints else None

    def _on_change(self, change: Change) -> None:
        if change in (Change.PROGRAM, Change.RUN):
            self.redraw()

    def redraw(self) -> None:
        last = self.last_waypoint()
        shown = render_row(
            {
                "record": self.record._impl.uuid,
                "close": self.record_close._impl.uuid,
                "open": self.record_open._impl.uuid,
                "run": self.run._impl.uuid,
            },
            last,
            run_line(self._programs.progress.state, len(self._programs.lines())),
            disabled=self._locked,
        )
        if shown != self.row.content:
            self.row.content = shown


RUN_WORDS = {
    RunState.RUNNING: "running…",
    RunState.PAUSED: "paused",
    RunState.FINISHED: "done",
    RunState.STOPPED: "stopped",
    RunState.FAILED: "stopped",
}


def run_line(state: RunState, steps: int) -> str:
    """Under Run: how the run goes, or how long the program is."""
    return RUN_WORDS.get(state, f"{steps} step{'' if steps == 1 else 's'}")


def render_row(uuids: dict[str, str], last: str | None, run_text: str, *, disabled: bool) -> str:
    off = ' disabled aria-disabled="true"' if disabled else ""
    dim = ";opacity:0.45;cursor:not-allowed" if disabled else ""

    def button(key: str, main: str, sub: str, title: str, look: str = "") -> str:
        tip = VIEW_ONLY_HINT if disabled else title
        return (
            f'<button type="button" data-click-uuid="{uuids[key]}" data-teach="{key}"'
            f' title="{html.escape(tip)}"'
            f' style="{TEACH_BUTTON_STYLE};{look}{dim}"{off}>{main}'
            f'<span style="{SUB_STYLE}">{html.escape(sub)}</span></button>'
        )

    last_text = f"last {last}" if last is not None else "none yet"
    row = "".join(
        (
            button("record", "Record", last_text, "A move to a new waypoint where the arm is", RECORD_STYLE),
            button("close", "Record", "+ close", "Record, then close the gripper"),
            button("open", "Record", "+ open", "Record, then open the gripper"),
            button("run", "Run", run_text, "Run the program from the start", RUN_STYLE),
        )
    )
    return inset(
        '<div id="teach-bar" role="group" aria-label="Teach" style="display:grid;'
        f'grid-template-columns:1.2fr 1fr 1fr 1fr;gap:6px;margin:4px 0 6px">{row}</div>'
    )
