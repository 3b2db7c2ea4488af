"""Older program files in today's schema: version 1 kept each waypoint inside its move step."""

from __future__ import annotations

from typing import Any

from pendant.program.models import SCHEMA_VERSION


def migrate(document: dict[str, Any]) -> dict[str, Any]:
    """`document` (a parsed file of any known version) as a schema-version-2 document."""
    if document.get("schema_version") == 1:
        document = _from_v1(document)
    return document


def _from_v1(document: dict[str, Any]) -> dict[str, Any]:
    """Lift every move's inline waypoint into the waypoint table; the move keeps only its name."""
    waypoints: list[Any] = []
    steps: list[Any] = []
    raw_steps = document.get("steps", [])
    for step in raw_steps if isinstance(raw_steps, list) else []:
        if (
            isinstance(step, dict)
            and step.get("kind", "move") == "move"
            and isinstance(step.get("waypoint"), dict)
        ):
            waypoints.append(step["waypoint"])
            step = {**step, "waypoint": step["waypoint"].get("name")}
        steps.append(step)
    return {**document, "schema_version": SCHEMA_VERSION, "waypoints": waypoints, "steps": steps}
