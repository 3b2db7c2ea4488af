"""The jog pad's markup: one row per axis, - and + either side of the axis' live value (as PolyScope and xArm
lay it out), and a line saying when the 250 mm/s TCP limit slows a joint jog.

The buttons are plain HTML driven by the page's script (client_page.js): it reads `data-jog-uuid` (the hidden
viser button whose hold and click messages it sends) and `data-jog-stop` (the hidden button that only stops).
The pad's markup changes only with the frame or the role: its live values come in a small element of their
own (`render_values`), which the script copies into the pad's labels in place. A pad rebuilt on every value
would re-create its buttons several times a second while the arm moves, and the keyboard focus on one of
them would fall to the page's body.
"""

from __future__ import annotations

import functools
import html
import math
from dataclasses import dataclass

import numpy as np

from pendant.jog import JOG_TCP_MAX_VELOCITY_M_S, JogFrame
from pendant.jog.targets import CARTESIAN_AXES
from pendant.kinematics import ArmModel
from pendant.kinematics.limits import JOINT_MAX_SPEED_RAD_S
from pendant.ui.kit.html import inset
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.kit.view_only import VIEW_ONLY_HINT

CAP_PROBE_RAD = 1e-4  # a small turn of one joint, to see how fast the TCP moves per radian
BUTTON_STYLE = (
    "height:34px;font-size:1.3em;font-weight:bold;border:1px solid #adb5bd;border-radius:6px;"
    "background:#f1f3f5;color:#212529;touch-action:pan-y;user-select:none;-webkit-user-select:none;"
    "-webkit-touch-callout:none;cursor:pointer"
)


@dataclass(frozen=True)
class CapNote:
    axis: int
    capped_deg_s: float
    asked_deg_s: float


def axis_name(frame: JogFrame, axis: int) -> str:
    return f"J{axis + 1}" if frame is JogFrame.JOINT else CARTESIAN_AXES[axis]


def axis_values(frame: JogFrame, snapshot: Snapshot) -> list[str]:
    """The live value of each axis: joint angles, or the TCP's position (mm) and rotation (°)."""
    if frame is JogFrame.JOINT:
        if snapshot.q is None:
            return ["–"] * 6
        return [f"{math.degrees(v):.1f}°" for v in snapshot.q]
    if snapshot.position is None:
        return ["–"] * 6
    p, r = snapshot.position.point, snapshot.position.rotation
    return [f"{v * 1000:.1f} mm" for v in (p.x, p.y, p.z)] + [
        f"{math.degrees(v):.1f}°" for v in (r.roll, r.pitch, r.yaw)
    ]


def tcp_capped_joint_speeds(
    arm: ArmModel, q: np.ndarray, T_flange_tool: np.ndarray, speed_percent: float
) -> list[CapNote]:
    """The joints whose jog at `speed_percent` would move the TCP faster than 250 mm/s here, with the speed
    the controller will actually give them (it scales the motion down to the TCP limit). Every browser's pad
    asks the same of the same pose several times a second (7 forward kinematics each): worked out once."""
    q_key = np.asarray(q, dtype=float).tobytes()
    tool_key = np.asarray(T_flange_tool, dtype=float).tobytes()
    return list(_capped(arm, q_key, tool_key, float(speed_percent)))


@functools.lru_cache(maxsize=32)
def _capped(arm: ArmModel, q_key: bytes, tool_key: bytes, speed_percent: float) -> tuple[CapNote, ...]:
    q = np.frombuffer(q_key, dtype=float).copy()
    T_flange_tool = np.frombuffer(tool_key, dtype=float).reshape(4, 4)
    tcp = (arm.fk(q) @ T_flange_tool)[:3, 3]
    notes = []
    for axis in range(6):
        probe = q.copy()
        probe[axis] += CAP_PROBE_RAD
        metres_per_rad = float(np.linalg.norm((arm.fk(probe) @ T_flange_tool)[:3, 3] - tcp)) / CAP_PROBE_RAD
        asked = float(JOINT_MAX_SPEED_RAD_S[axis]) * speed_percent / 100.0
        if metres_per_rad * asked > JOG_TCP_MAX_VELOCITY_M_S:
            capped = JOG_TCP_MAX_VELOCITY_M_S / metres_per_rad
            notes.append(CapNote(axis, math.degrees(capped), math.degrees(asked)))
    return tuple(notes)


def cap_line(notes: list[CapNote]) -> str:
    if not notes:
        return ""
    parts = ", ".join(f"J{n.axis + 1} to {n.capped_deg_s:.0f}°/s (of {n.asked_deg_s:.0f})" for n in notes)
    return f"The 250 mm/s TCP limit slows {parts} here."


VALUES_SEPARATOR = "|"


def render_values(values: list[str]) -> str:
    """The live values, for the script to put in the pad (hidden: the pad shows them)."""
    joined = html.escape(VALUES_SEPARATOR.join(values))
    return f'<div hidden data-jog-values="{joined}"></div>'


def render_note(note: str) -> str:
    return inset(f'<div style="font-size:0.8em;color:#b8420c" id="jog-cap-note">{html.escape(note)}</div>')


def render_pad(
    frame: JogFrame,
    values: list[str],
    uuids: dict[tuple[int, int], str],
    stop_uuid: str,
    *,
    disabled: bool,
    line: str = "",
) -> str:
    """The pad; `values` are those it opens with (the script keeps them current: see `render_values`);
    `line`: "PORT KEY" of this browser's hold line (pendant/ui/kit/hold_line.py), "" for none."""
    # A viewer's pad: greyed out, and the tooltip says why (not buttons that look active and do nothing).
    off = ' disabled aria-disabled="true"' if disabled else ""
    look = BUTTON_STYLE + (";opacity:0.45;cursor:not-allowed" if disabled else "")
    rows = []
    for axis in range(6):
        name = axis_name(frame, axis)
        buttons = {
            direction: (
                f'<button type="button" data-jog-uuid="{uuids[(axis, direction)]}" aria-label="{name}{sign}" '
                f'tabindex="{0 if (axis, direction) == (0, -1) else -1}" '
                f'title="{VIEW_ONLY_HINT if disabled else f"Hold to jog {name}{sign}"}" style="{look}"{off}>'
                f"{symbol}</button>"
            )
            for direction, sign, symbol in ((-1, "-", "−"), (+1, "+", "+"))
        }
        rows.append(
            f'<div style="display:grid;grid-template-columns:64px 1fr 64px;gap:6px;align-items:center;'
            f'margin-bottom:3px">{buttons[-1]}<div style="text-align:center;white-space:nowrap">'
            f'<span style="font-size:0.85em;color:#495057">{name}</span> '
            f'<b data-jog-value="{axis}">{html.escape(values[axis])}</b></div>{buttons[+1]}</div>'
        )
    line_attribute = f' data-jog-line="{html.escape(line)}"' if line else ""
    # One Tab stop for the whole pad (J1- until another is used); the arrow keys move inside it (jog_keys.js).
    return inset(
        f'<div data-jog-stop="{stop_uuid}"{line_attribute} id="jog-pad" role="group" '
        f'aria-label="Jog pad (arrow keys move between its buttons)">{"".join(rows)}</div>'
    )
