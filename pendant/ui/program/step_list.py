"""The Program tab's step list as text: the lines of the Step dropdown, and the Markdown list that marks the
selected, running and failed step (and the Check's verdict on each)."""

from __future__ import annotations

from collections.abc import Callable

from pendant.program import RunProgress, describe_step
from pendant.program.tree import Line

INDENT = "\u2003"  # an em space: Markdown keeps it, so nesting shows


def step_label(line: Line) -> str:
    prefix = "Else: " if line.branch == "otherwise" else ""
    return prefix + describe_step(line.step)


def dropdown_lines(listed: list[Line]) -> list[str]:
    """The Step dropdown's options: "1. Move J to P1 @ 20%", nested lines indented."""
    return [f"{i + 1}. {INDENT * line.depth}{step_label(line)}" for i, line in enumerate(listed)]


def steps_markdown(
    listed: list[Line], progress: RunProgress, selected: int | None, check_mark: Callable[[int], str]
) -> str:
    """The step list, the failed (✖), running (▶) or selected (●) line in bold."""
    current = progress.step_index if progress.active else None
    rows = []
    for i, line in enumerate(listed):
        mark = "✖" if i == progress.failed_step else "▶" if i == current else "●" if i == selected else ""
        # "4\." is not a Markdown list item: the list can never renumber itself around a bold line.
        text = f"{mark} {i + 1}\\. {'&emsp;' * line.depth}{step_label(line)}{check_mark(i)}"
        rows.append(f"**{text}**" if mark else text)
    return "  \n".join(rows) if rows else "_No steps: jog the arm and press Record._"
