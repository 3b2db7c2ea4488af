"""The status readout: mode, connection, system state, motion state (coloured), joints, TCP, tool, gripper
and IO; under it one button: a protective Stop, or Recover when the arm is stopped in error."""

from __future__ import annotations

import html
import math
import time

import viser

from pendant.controller import MotionStatus, SignalLevel
from pendant.controller.system_types import FailureType
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset
from pendant.ui.kit.readout_rates import readout_period_s
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.kit.stop_path import on_stop_press
from pendant.ui.robot.safety_panel import PROTECTIVE_STOP_HINT, render_system_state

STATE_COLOURS: dict[MotionStatus | None, str] = {
    MotionStatus.IDLE: "#237032",
    MotionStatus.RUNNING: "#1971c2",
    MotionStatus.ZERO_GRAVITY: "#9c36b5",
    MotionStatus.MOTION_FAILED: "#e8590c",
    MotionStatus.ERROR: "#e03131",
    MotionStatus.EMERGENCY: "#c92a2a",
    None: "#868e96",
}
_ALARM_STATES = {MotionStatus.ERROR, MotionStatus.EMERGENCY, MotionStatus.MOTION_FAILED}
# The controller's round trip is shown from here on, in steps of it: below, a link is fine and its number
# would only flicker (the simulator's 0-2 ms changed the block 3 times a second at rest: 2.4 KB to every
# browser each time, and a re-render of each page).
SLOW_LINK_S = 0.010


def _led(level: SignalLevel | None, label: str) -> str:
    on = level is SignalLevel.HIGH
    colour = "#40c057" if on else "#dee2e6"
    return (
        f'<span style="display:inline-block;margin-right:8px"><span style="display:inline-block;width:10px;'
        f'height:10px;border-radius:5px;background:{colour};margin-right:3px"></span>{label}</span>'
    )


MSG_PROTECTIVE_STOP_SHOWN = "Protective stop - Recover to continue"


def in_protective_stop(snapshot: Snapshot, state: CellState) -> bool:
    """Stopped in error, and the controller's newest failure is its protective stop (STOP_2): only Recover
    leaves it (Freeze does not)."""
    return (
        snapshot.motion_status is MotionStatus.ERROR
        and bool(state.failures)
        and state.failures[-1].type is FailureType.STOP_2
    )


def render_status(snapshot: Snapshot, mode_line: str, system: str = "", protective: bool = False) -> str:
    """The status block as HTML; ERROR and EMERGENCY fill a red banner that cannot be missed. `system`: the
    system state's fragment (safety_panel.render_system_state), on the first line. `protective`: the
    banner says it is a protective stop, which only Recover leaves."""
    state = snapshot.motion_status
    if state is not None:
        label, colour = state.value, STATE_COLOURS[state]
    elif snapshot.online:  # it answered, but with an error (500 "Robot does not respond")
        label, colour = "NO RESPONSE", STATE_COLOURS[MotionStatus.ERROR]
    else:
        label, colour = "OFFLINE", STATE_COLOURS[None]
    big = "font-size:1.4em;padding:10px" if state in _ALARM_STATES or state is None else "padding:6px"
    link = "online" if snapshot.online else "offline"
    if snapshot.online and snapshot.latency_s is not None and snapshot.latency_s >= SLOW_LINK_S:
        link += f" · {round(snapshot.latency_s / SLOW_LINK_S) * SLOW_LINK_S * 1000:.0f} ms"
    system = f" · {system}" if system else ""
    # On a phone the block folds to this first line (touch_layout.js hides the `phone-fold` parts).
    parts = [
        '<div id="status-line" class="status-line">'
        f'<div style="font-size:0.85em;color:#495057">{html.escape(mode_line)} · {link}{system}</div>'
        f'<div id="motion-state" style="background:{colour};color:white;font-weight:bold;'
        f'text-align:center;border-radius:6px;margin:6px 0;{big}">{label}</div></div>',
    ]
    if protective:
        parts.append(
            '<div id="protective-stop" style="color:#e03131;font-weight:bold">'
            f"{MSG_PROTECTIVE_STOP_SHOWN}</div>"
        )
    if snapshot.error:
        parts.append(f'<div style="color:#e03131">{html.escape(snapshot.error)}</div>')
    parts.append(f'<div class="phone-fold">{_where(snapshot)}</div>')
    opening = snapshot.gripper_opening
    gripper = "unknown" if opening is None else "open" if opening > 0.5 else "closed"
    parts.append(
        f'<div class="phone-fold" style="font-size:0.85em">Tool <b>{html.escape(snapshot.tool_name)}</b> · '
        f"gripper <b>{gripper}</b> · id {html.escape(snapshot.robot_id)}</div>"
    )
    if snapshot.outputs or snapshot.inputs:
        leds = "".join(_led(level, f"DO{p}") for p, level in snapshot.outputs.items())
        leds += "".join(_led(level, f"DI{p}") for p, level in snapshot.inputs.items())
        parts.append(f'<div class="phone-fold" style="font-size:0.85em">{leds}</div>')
    return inset(f'<div id="status-block">{"".join(parts)}</div>')


def _where(snapshot: Snapshot) -> str:
    """Joints and TCP; in a fault (no reading), the last known ones greyed, with their age."""
    q, position, note, style = snapshot.q, snapshot.position, "", ""
    last = snapshot.last_known
    if q is None and last is not None:
        q, position = last.q, last.position
        age = max(0.0, snapshot.taken_at - last.taken_at)
        note = f'<div id="last-known" style="font-size:0.8em;color:#868e96">last known, {age:.0f} s ago</div>'
        style = "color:#adb5bd;"
    parts = [note]
    if q is not None:
        cells = "".join(
            f'<td style="text-align:right;padding:0 4px">J{i + 1}<br><b>{math.degrees(v):.1f}°</b></td>'
            for i, v in enumerate(q)
        )
        parts.append(
            f'<table id="joints" style="width:100%;font-size:0.85em;{style}"><tr>{cells}</tr></table>'
        )
    if position is not None:
        p, r = position.point, position.rotation
        parts.append(
            f'<div id="tcp" style="font-size:0.85em;font-family:monospace;{style}">'
            f"X {p.x * 1000:.1f} Y {p.y * 1000:.1f} Z {p.z * 1000:.1f} mm<br>"
            f"R {math.degrees(r.roll):.1f} P {math.degrees(r.pitch):.1f} "
            f"Y {math.degrees(r.yaw):.1f} °</div>"
        )
    return "".join(parts)


class _LastRendering:
    """render_status's last block, kept for the next browser: the refresh shows one snapshot to every
    browser in turn, and each rendered the same block again (a tenth of the pendant's time beside 60
    viewers, issue 37). One entry, keyed by the snapshot itself (not a copy), replaced as a whole."""

    def __init__(self) -> None:
        self._last: tuple[Snapshot, str, str, bool, str] | None = None

    def render(self, snapshot: Snapshot, mode_line: str, system: str, protective: bool) -> str:
        last = self._last
        if last is not None and last[0] is snapshot and last[1:4] == (mode_line, system, protective):
            return last[4]
        content = render_status(snapshot, mode_line, system, protective)
        self._last = (snapshot, mode_line, system, protective, content)
        return content


_rendering = _LastRendering()


# States Recover clears: in them the button under the banner is Recover, otherwise the protective Stop.
RECOVERABLE = {MotionStatus.ERROR, MotionStatus.MOTION_FAILED}


class StatusPanel:
    """The status, then one row: Protective stop (any browser may stop, like Freeze) or, once the arm is
    stopped in error, Recover (the operator's), in the same place. `recover_in_banner`: the page's banner
    offers Recover (page/banner.py), so this one stays hidden: one Recover on the page, and the banner alone
    names a protective stop."""

    def __init__(
        self, target: GuiTarget, mode_line: str, runner: CommandRunner, *, recover_in_banner: bool = False
    ) -> None:
        self._mode_line = mode_line
        self._recover_in_banner = recover_in_banner
        self._html = target.gui.add_html(render_status(Snapshot(taken_at=0.0), mode_line))
        self.stop = target.gui.add_button(
            "Protective stop", color="orange", icon=viser.Icon.HAND_OFF, hint=PROTECTIVE_STOP_HINT
        )
        self.recover = target.gui.add_button(
            "Recover", color="red", icon=viser.Icon.REFRESH, visible=False, hint="Clear the error and go on"
        )

        def stop(client: viser.ClientHandle | None) -> object:
            return runner.submit("Protective stop", lambda c: c.stop(), client, urgent=True)

        self.stop.on_click(on_stop_press(runner, stop))  # read on viser's event loop, like Freeze
        self.recover.on_click(lambda event: runner.submit("Recover", lambda c: c.recover(), event.client))
        self._snapshot = Snapshot(taken_at=0.0)
        self._system = render_system_state(CellState())
        self._cell_state = CellState()
        self._last = ""
        self._headline: tuple[object, ...] = ()  # what the last block sent said, but for the live values
        self._sent_at = 0.0
        self.viewer = False  # a browser without control: its live values less often (readout_rates.py)

    @property
    def content(self) -> str:
        return self._last

    def show(self, snapshot: Snapshot) -> None:
        self._snapshot = snapshot
        recoverable = snapshot.motion_status in RECOVERABLE
        if self.recover.visible != (recoverable and not self._recover_in_banner):
            self.recover.visible = recoverable and not self._recover_in_banner
        if self.stop.visible == recoverable:
            self.stop.visible = not recoverable
        self._render()

    def show_system(self, state: CellState) -> None:
        """The controller's system state (`/status`); without it (older firmware) the Stop is greyed out."""
        self._system = render_system_state(state)
        self._cell_state = state
        unsupported = "status" in state.unsupported
        if self.stop.disabled != unsupported:
            self.stop.disabled = unsupported
        self._render()

    def _render(self) -> None:
        # With the banner, it alone says "Protective stop" and the way out (one line, one Recover).
        protective = not self._recover_in_banner and in_protective_stop(self._snapshot, self._cell_state)
        content = _rendering.render(self._snapshot, self._mode_line, self._system, protective)
        if content == self._last:
            return
        snapshot, now = self._snapshot, time.monotonic()
        headline = (
            snapshot.motion_status,
            snapshot.online,
            snapshot.error,
            self._system,
            protective,
            snapshot.tool_name,
            snapshot.gripper_opening,
            snapshot.robot_id,
            tuple(snapshot.outputs.items()),
            tuple(snapshot.inputs.items()),
            snapshot.q is None,
            snapshot.last_known is None,
        )
        if headline == self._headline and now - self._sent_at < readout_period_s(self.viewer):
            return  # only the live values moved, and they were sent a moment ago: the next tick sends them
        self._html.content = content
        self._last, self._headline, self._sent_at = content, headline, now
