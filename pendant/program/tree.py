"""The step tree as numbered lines, and edits addressed by line: what the step list and the workspace use.

A path is (index, branch, index, branch, ..., index): (2,) is the third top-level step, (2, "body", 0) the
first step inside it. Lines number the tree depth first, as it is listed: a structure before what it holds.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pendant.program.models import Step, children

Path = tuple[int | str, ...]


@dataclass(frozen=True)
class Line:
    path: Path
    depth: int
    step: Step
    branch: str  # the branch of its parent it sits in ("" at the top level)


def lines(steps: tuple[Step, ...], prefix: Path = (), depth: int = 0, branch: str = "") -> list[Line]:
    found: list[Line] = []
    for index, step in enumerate(steps):
        path = (*prefix, index)
        found.append(Line(path, depth, step, branch))
        for name, inner in children(step):
            found.extend(lines(inner, (*path, name), depth + 1, name))
    return found


def get(steps: tuple[Step, ...], path: Path) -> Step:
    step = steps[int(path[0])]
    if len(path) == 1:
        return step
    return get(getattr(step, str(path[1])), path[2:])


def _rebuild(
    steps: tuple[Step, ...], path: Path, change: Callable[[tuple[Step, ...]], tuple[Step, ...]]
) -> tuple[Step, ...]:
    """`steps` with the list that holds `path`'s last index replaced by change(that list)."""
    if len(path) == 1:
        return change(steps)
    index, branch = int(path[0]), str(path[1])
    parent = steps[index]
    inner = _rebuild(getattr(parent, branch), path[2:], change)
    updated = type(parent).model_validate({**dict(parent), branch: inner})
    return (*steps[:index], updated, *steps[index + 1 :])


def replace(steps: tuple[Step, ...], path: Path, step: Step) -> tuple[Step, ...]:
    i = int(path[-1])
    return _rebuild(steps, path, lambda s: (*s[:i], step, *s[i + 1 :]))


def insert(steps: tuple[Step, ...], path: Path, step: Step) -> tuple[Step, ...]:
    """Insert so that `step` ends up at `path` (its index may be one past the end of its list)."""
    i = int(path[-1])
    return _rebuild(steps, path, lambda s: (*s[:i], step, *s[i:]))


def delete(steps: tuple[Step, ...], path: Path) -> tuple[Step, ...]:
    i = int(path[-1])
    return _rebuild(steps, path, lambda s: (*s[:i], *s[i + 1 :]))


def sibling_count(steps: tuple[Step, ...], path: Path) -> int:
    if len(path) == 1:
        return len(steps)
    return len(getattr(get(steps, path[:-2]), str(path[-2])))
