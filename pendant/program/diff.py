"""What changed between two versions of a program, in the operator's words.

"P3 moved +12.0 mm in X", "step 7 (Move J to P3 @ 20%): speed 20 -> 40 %", "step 9 (Wait DI2 high ...)
added", "waypoint P3 renamed to Pick". A renamed waypoint is followed through the steps, so its moves are
not reported as changed; steps are numbered as the step list numbers them (removed ones by their old number).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass
from typing import Any

from pendant.controller.types import Position
from pendant.program import tree
from pendant.program.describe import describe_step
from pendant.program.models import BRANCHES, MoveStep, PalletStep, PathStep, Program, Step, Waypoint

MOVE_TOL_MM = 0.001  # a micrometre: below it, a waypoint has not moved (files keep nanometres)
TURN_TOL_DEG = 0.001
SUMMARY_ITEMS = 2  # changes named in a commit message's first line
_UNITS = {"speed": "%", "timeout_ms": "ms", "ms": "ms", "blend_mm": "mm", "approach_mm": "mm"}
_UNITS |= {"layer_height_mm": "mm", "tol_mm": "mm", "tol_deg": "°", "velocity_mm_s": "mm/s"}
_LABELS = {"blend_mm": "blend", "timeout_ms": "timeout", "ms": "wait", "approach_mm": "approach"}
_LABELS |= {"layer_height_mm": "layer height", "tol_mm": "tolerance", "tol_deg": "angle tolerance"}
_LABELS |= {"velocity_mm_s": "velocity", "program": "calls"}


@dataclass(frozen=True)
class WaypointMove:
    """A waypoint taught somewhere else: where it was and where it is (its name in the newer version)."""

    name: str
    before: Position
    after: Position

    @property
    def distance_mm(self) -> float:
        a, b = self.before.point, self.after.point
        return 1000.0 * math.dist((a.x, a.y, a.z), (b.x, b.y, b.z))


@dataclass(frozen=True)
class ProgramDiff:
    lines: tuple[str, ...]  # one change a line, waypoints first, then steps in list order
    moved: tuple[WaypointMove, ...]

    @property
    def changed(self) -> bool:
        return bool(self.lines)

    def summary(self, items: int = SUMMARY_ITEMS) -> str:
        """The first changes on one line: "P3 moved +12.0 mm in X; step 2 (Wait 500 ms) added (+3 more)"."""
        if not self.lines:
            return "no change"
        text = "; ".join(self.lines[:items])
        rest = len(self.lines) - items
        return text + (f" (+{rest} more)" if rest > 0 else "")


def diff_programs(old: Program, new: Program) -> ProgramDiff:
    """The changes that make `old` into `new` (their waypoints and steps)."""
    lines: list[str] = []  # (the names are the files' names, not content: the caller says which files)
    renames = _renames(old, new)
    lines += [f"waypoint {a} renamed to {b}" for a, b in renames.items()]
    old_points = {renames.get(w.name, w.name): w for w in old.waypoints}
    moved: list[WaypointMove] = []
    for waypoint in new.waypoints:
        before = old_points.get(waypoint.name)
        if before is None:
            p = waypoint.position.point
            where = f"({1000 * p.x:.1f}, {1000 * p.y:.1f}, {1000 * p.z:.1f}) mm"
            lines.append(f"waypoint {waypoint.name} added at {where}")
            continue
        change = _waypoint_change(before, waypoint)
        if change:
            lines.append(f"{waypoint.name} {change}")
            if _mm_moved(before.position, waypoint.position) or _turned(before.position, waypoint.position):
                moved.append(WaypointMove(waypoint.name, before.position, waypoint.position))
    new_names = set(new.waypoint_names())
    lines += [f"waypoint {n} removed" for n, w in old_points.items() if n not in new_names]
    lines += _step_changes(old, new, renames)
    return ProgramDiff(tuple(lines), tuple(moved))


# --- waypoints -------------------------------------------------------------------------------------------
def _renames(old: Program, new: Program) -> dict[str, str]:
    """Old name -> new name for waypoints that only changed name: the same place, else the same row."""
    new_names, old_names = set(new.waypoint_names()), set(old.waypoint_names())
    gone = [w for w in old.waypoints if w.name not in new_names]
    came = [w for w in new.waypoints if w.name not in old_names]
    renames: dict[str, str] = {}
    for before in gone:
        twin = next((w for w in came if _waypoint_change(before, w) == ""), None)
        if twin is not None:
            renames[before.name] = twin.name
            came.remove(twin)
    row = {w.name: i for i, w in enumerate(new.waypoints)}
    for i, before in enumerate(old.waypoints):  # re-taught and renamed: the rename keeps its row
        if before in gone and before.name not in renames:
            twin = next((w for w in came if row[w.name] == i), None)
            if twin is not None:
                renames[before.name] = twin.name
                came.remove(twin)
    return renames


def _mm_moved(a: Position, b: Position) -> list[tuple[str, float]]:
    pa, pb = a.point, b.point
    deltas = (("X", pb.x - pa.x), ("Y", pb.y - pa.y), ("Z", pb.z - pa.z))
    return [(axis, 1000.0 * d) for axis, d in deltas if abs(1000.0 * d) >= MOVE_TOL_MM]


def _angle(delta_rad: float) -> float:
    return (math.degrees(delta_rad) + 180.0) % 360.0 - 180.0


def _turned(a: Position, b: Position) -> list[tuple[str, float]]:
    ra, rb = a.rotation, b.rotation
    deltas = (("roll", rb.roll - ra.roll), ("pitch", rb.pitch - ra.pitch), ("yaw", rb.yaw - ra.yaw))
    return [(axis, _angle(d)) for axis, d in deltas if abs(_angle(d)) >= TURN_TOL_DEG]


def _number(value: float) -> str:
    return f"{value:+.1f}" if abs(value) >= 0.05 else f"{value:+.3f}"


def _waypoint_change(a: Waypoint, b: Waypoint) -> str:
    """ "moved +12.0 mm in X and turned +0.5° in yaw", "" when it has not changed."""
    moved, turned = _mm_moved(a.position, b.position), _turned(a.position, b.position)
    parts = []
    if len(moved) == 1:
        parts.append(f"moved {_number(moved[0][1])} mm in {moved[0][0]}")
    elif moved:
        distance = WaypointMove(b.name, a.position, b.position).distance_mm
        parts.append(f"moved {distance:.1f} mm ({', '.join(f'{_number(d)} in {x}' for x, d in moved)})")
    if len(turned) == 1:
        parts.append(f"turned {_number(turned[0][1])}° in {turned[0][0]}")
    elif turned:
        parts.append(f"turned ({', '.join(f'{_number(d)}° in {x}' for x, d in turned)})")
    if parts:
        return " and ".join(parts)
    joints = [
        f"J{i + 1} {_number(_angle(math.radians(y - x)))}°"
        for i, (x, y) in enumerate(zip(a.pose.angles, b.pose.angles, strict=True))
        if abs(_angle(math.radians(y - x))) >= TURN_TOL_DEG
    ]
    return f"same place, other joint angles ({', '.join(joints)})" if joints else ""


# --- steps -----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Row:
    number: int  # as the step list shows it, from 1
    step: Step
    text: str  # describe_step in its own version's words
    key: str  # what must be equal for two rows to be the same step (old names mapped to new ones)
    place: str  # depth and branch: the same step indented is moved, not changed


def _rows(program: Program, renames: dict[str, str]) -> list[_Row]:
    rows = []
    for number, line in enumerate(tree.lines(program.steps), start=1):
        key = describe_step(_renamed(line.step, renames))
        rows.append(_Row(number, line.step, describe_step(line.step), key, f"{line.depth}{line.branch}"))
    return rows


def _renamed(step: Step, renames: dict[str, str]) -> Step:
    if not renames:
        return step
    if isinstance(step, MoveStep):
        return step.model_copy(update={"waypoint": renames.get(step.waypoint, step.waypoint)})
    if isinstance(step, PalletStep):
        return step.model_copy(update={"corners": tuple(renames.get(c, c) for c in step.corners)})
    return step


def _step_changes(old: Program, new: Program, renames: dict[str, str]) -> list[str]:
    before, after = _rows(old, renames), _rows(new, {})
    matcher = difflib.SequenceMatcher(
        None, [(r.place, r.key) for r in before], [(r.place, r.key) for r in after], autojunk=False
    )
    removed: list[_Row] = []
    added: list[_Row] = []
    changed: list[tuple[_Row, _Row]] = []
    for op, i1, i2, j1, j2 in matcher.get_opcodes():
        olds, news = before[i1:i2], after[j1:j2]
        if op == "replace":  # same kind at the same place: one step edited
            while olds and news and type(olds[0].step) is type(news[0].step):
                changed.append((olds.pop(0), news.pop(0)))
        if op != "equal":
            removed += olds
            added += news
    lines: list[tuple[int, str]] = []
    for row in list(added):  # the same step taken out here and put in there: moved
        twin = next((r for r in removed if r.key == row.key), None)
        if twin is not None:
            removed.remove(twin)
            added.remove(row)
            lines.append((row.number, f"step {twin.number} ({twin.text}) moved to step {row.number}"))
    lines += [
        (a.number, f"step {a.number} ({a.text}): {_fields(b.step, a.step, renames)}") for b, a in changed
    ]
    lines += [(r.number, f"step {r.number} ({r.text}) added") for r in added]
    lines += [(r.number, f"step {r.number} ({r.text}) removed") for r in removed]
    return [text for _, text in sorted(lines, key=lambda item: item[0])]


def _fields(old: Step, new: Step, renames: dict[str, str]) -> str:
    """ "speed 20 -> 40 %, motion joint -> linear": the fields of one step that differ."""
    branches = set(BRANCHES.get(type(new), ()))
    a = _renamed(old, renames).model_dump(mode="json", exclude=branches)
    b = new.model_dump(mode="json", exclude=branches)
    parts = [_field(name, a.get(name), value) for name, value in b.items() if a.get(name) != value]
    if isinstance(new, PathStep) and isinstance(old, PathStep):
        parts = [p for p in parts if not p.startswith("points")]
        if len(old.points) != len(new.points):
            parts.append(f"{len(new.points)} waypoints (was {len(old.points)})")
        elif old.points != new.points:
            parts.append("recorded waypoints changed")
    if any(part.endswith(" changed") for part in parts):
        parts.append(f"was: {describe_step(old)}")
    return ", ".join(parts) or describe_step(new)


def _field(name: str, before: Any, after: Any) -> str:
    if name == "times":
        return f"now {after} times (was {before})"
    if name == "waypoint":
        return f"goes to {after} (was {before})"
    if isinstance(before, int | float | str) and isinstance(after, int | float | str):
        unit = f" {_UNITS[name]}" if name in _UNITS else ""
        return f"{_LABELS.get(name, name)} {_scalar(before)} -> {_scalar(after)}{unit}"
    return f"{_LABELS.get(name, name)} changed"


def _scalar(value: int | float | str) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)
