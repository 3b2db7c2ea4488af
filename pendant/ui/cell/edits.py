"""What the Cell tab's edits may do, apart from the widgets: the default fields of each kind, and the rule
that an edit changes only what the operator chose (Update never adds, Add never replaces)."""

from __future__ import annotations

from pendant.cell.forms import ObstacleForm
from pendant.controller import Controller

NEW = "(new obstacle)"
DEFAULT_FORMS = {
    "BOX": ObstacleForm(kind="BOX", name="box", at_mm=(400.0, 0.0, 100.0), size_mm=(200.0, 200.0, 200.0)),
    "CAPSULE": ObstacleForm(
        kind="CAPSULE", name="post", at_mm=(400.0, 300.0, 0.0), end_mm=(400.0, 300.0, 500.0), radius_mm=40.0
    ),
    "PLANE": ObstacleForm(kind="PLANE", name="wall", at_mm=(0.0, -500.0, 0.0), rpy_deg=(90.0, 0.0, 0.0)),
}


def edit_refusal(names: set[str], old: str | None, new: str) -> tuple[str, str] | None:
    """(title, reason) when the edit would surprise, else None. `old`: the obstacle Update changes (None for
    Add); `new`: the name in the fields. The controller keeps obstacles by name: adding or renaming onto a
    name in use would silently replace that obstacle."""
    if old == NEW or (old is not None and old not in names):
        return "Nothing updated", "choose an obstacle in the list first, or press Add obstacle"
    if new in names and new != old:
        title = "Obstacle not added" if old is None else "Obstacle not renamed"
        return title, f"an obstacle is already called {new!r}: pick another name"
    return None


def clear_cell(c: Controller) -> object:
    return c.remove_obstacles()
