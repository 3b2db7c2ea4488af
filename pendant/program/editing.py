"""Edits of the program being taught: the waypoint table and the step tree, addressed by step-list line.

Every edit builds a new Program, validated whole, and hands it to `_commit` (the workspace: autosave, undo
history, notify). A refused edit raises EditError and changes nothing.
"""

from __future__ import annotations

import re
import threading

from pydantic import ValidationError

from pendant.controller import Controller, Pose, Position
from pendant.controller.types import MotionType
from pendant.program import tree
from pendant.program.limits import WAYPOINT_NAME_MAX
from pendant.program.models import (
    DEFAULT_SPEED_PERCENT,
    STRUCTURES,
    MoveStep,
    PalletStep,
    Program,
    Step,
    Waypoint,
    children,
    describe_problems,
    referenced_waypoints,
)


class EditError(Exception):
    """An edit the workspace refuses (bad line, duplicate waypoint name); `str()` says why."""


class ProgramEditing:
    """The editing half of ProgramWorkspace; `_program`, `_lock` and `_commit` come from it."""

    _program: Program
    _lock: threading.RLock

    def _commit(self, program: Program) -> None:
        raise NotImplementedError

    # --- building blocks -------------------------------------------------------------------------------
    def _edit(
        self, steps: tuple[Step, ...] | list[Step], waypoints: tuple[Waypoint, ...] | None = None
    ) -> None:
        with self._lock:
            fields = {**dict(self._program), "steps": tuple(steps)}
            if waypoints is not None:
                fields["waypoints"] = waypoints
            try:  # validated whole, as a load would: an edit never saves what could not be read back
                program = Program.model_validate(fields)
            except ValidationError as error:
                raise EditError(describe_problems(error, limit=1)) from error
            self._commit(program)

    def lines(self) -> list[tree.Line]:
        return tree.lines(self._program.steps)

    def _line(self, index: int) -> tree.Line:
        listed = self.lines()
        if not 0 <= index < len(listed):
            raise EditError(f"There is no step {index + 1}")
        return listed[index]

    def _move(self, index: int) -> MoveStep:
        step = self._line(index).step
        if not isinstance(step, MoveStep):
            raise EditError(f"Step {index + 1} is not a move")
        return step

    def _line_of(self, path: tree.Path) -> int:
        return next(i for i, line in enumerate(self.lines()) if line.path == path)

    # --- steps ---------------------------------------------------------------------------------------
    def insert_step(self, step: Step, *, after: int | None = None, waypoint: Waypoint | None = None) -> int:
        """Insert after line `after` (in the same list; at the end when None); returns the new line.

        `waypoint`: a new waypoint for the table, placed so the table reads in program order."""
        with self._lock:
            steps = self._program.steps
            if after is None:
                path: tree.Path = (len(steps),)
            else:
                at = self._line(after).path
                path = (*at[:-1], int(at[-1]) + 1)
            updated = tree.insert(steps, path, step)
            waypoints = None
            if waypoint is not None:
                waypoints = self._with_waypoint(waypoint, updated, path)
            self._edit(updated, waypoints)
            return self._line_of(path)

    def insert_into(self, index: int, step: Step, branch: str | None = None) -> int:
        """Put `step` first inside the structure at line `index` (its first branch unless `branch`)."""
        with self._lock:
            line = self._line(index)
            names = [name for name, _ in children(line.step)]
            if not names:
                raise EditError(f"Step {index + 1} holds no steps (only Loop, If and Pallet do)")
            chosen = branch or names[0]
            if chosen not in names:
                raise EditError(f"Step {index + 1} has no {chosen!r} branch")
            path = (*line.path, chosen, 0)
            self._edit(tree.insert(self._program.steps, path, step))
            return self._line_of(path)

    def replace_step(self, index: int, step: Step) -> None:
        with self._lock:
            old = self._line(index)
            if isinstance(step, STRUCTURES) and type(step) is type(old.step):
                # A structure's fields changed: what it holds stays (the form does not carry it).
                step = step.model_copy(update=dict(children(old.step)))
            self._edit(tree.replace(self._program.steps, old.path, step))

    def delete_step(self, index: int) -> None:
        """Delete the step at line `index` (a structure with everything it holds)."""
        with self._lock:
            self._edit(tree.delete(self._program.steps, self._line(index).path))

    def move_step(self, index: int, delta: int) -> int:
        """Move the step at line `index` up (delta -1) or down (+1) within its list; returns its line."""
        with self._lock:
            path = self._line(index).path
            steps = self._program.steps
            i, count = int(path[-1]), tree.sibling_count(steps, path)
            to = min(max(i + delta, 0), count - 1)
            if to == i:
                return index
            step = tree.get(steps, path)
            moved = tree.insert(tree.delete(steps, path), (*path[:-1], to), step)
            self._edit(moved)
            return self._line_of((*path[:-1], to))

    def indent(self, index: int) -> int:
        """Move the step into the Loop / If / Pallet just above it (at the end of its last branch)."""
        with self._lock:
            path = self._line(index).path
            i = int(path[-1])
            steps = self._program.steps
            above = tree.get(steps, (*path[:-1], i - 1)) if i > 0 else None
            if above is None or not children(above):
                raise EditError(
                    "Indent puts a step into a Loop, If or Pallet: the step above is none of those"
                )
            branch, inner = children(above)[-1]
            step = tree.get(steps, path)
            target = (*path[:-1], i - 1, branch, len(inner))
            self._edit(tree.insert(tree.delete(steps, path), target, step))
            return self._line_of(target)

    def outdent(self, index: int) -> int:
        """Move the step out of the structure that holds it, to just after that structure."""
        with self._lock:
            path = self._line(index).path
            if len(path) == 1:
                raise EditError(f"Step {index + 1} is not inside a Loop, If or Pallet")
            steps = self._program.steps
            step = tree.get(steps, path)
            parent = path[:-2]
            target = (*parent[:-1], int(parent[-1]) + 1)
            self._edit(tree.insert(tree.delete(steps, path), target, step))
            return self._line_of(target)

    def duplicate_step(self, index: int) -> int:
        """A copy right after the step; a move goes to a copy of its waypoint ("P1 copy"), to re-teach."""
        with self._lock:
            step = self._line(index).step
            if not isinstance(step, MoveStep):
                return self.insert_step(step, after=index)
            original = self._program.waypoint(step.waypoint)
            names = set(self._program.waypoint_names())
            room = WAYPOINT_NAME_MAX - len(f" {len(names) + 1}")  # for the " k" that keeps it unique
            base = f"{original.name} copy"[:room].rstrip()
            name = next(
                n for k in range(1, len(names) + 2) if (n := base if k == 1 else f"{base} {k}") not in names
            )
            copy = original.model_copy(update={"name": name})
            return self.insert_step(step.model_copy(update={"waypoint": name}), after=index, waypoint=copy)

    # --- waypoints -----------------------------------------------------------------------------------
    def next_waypoint_name(self) -> str:
        names = set(self._program.waypoint_names())
        numbers = [int(m.group(1)) for n in names if (m := re.fullmatch(r"P(\d+)", n))]
        return f"P{max(numbers, default=0) + 1}"

    def record(
        self,
        pose: Pose,
        position: Position,
        *,
        after: int | None = None,
        name: str | None = None,
        motion: MotionType = MotionType.JOINT,
        speed: float = DEFAULT_SPEED_PERCENT,
    ) -> int:
        """Add a move to a new waypoint (after line `after`, else at the end); returns its line."""
        with self._lock:
            waypoint = Waypoint(
                name=self._unique_name(name or self.next_waypoint_name()), pose=pose, position=position
            )
            step = MoveStep(waypoint=waypoint.name, motion=motion, speed=speed)
            return self.insert_step(step, after=after, waypoint=waypoint)

    def record_from(
        self,
        controller: Controller,
        *,
        after: int | None = None,
        name: str | None = None,
        motion: MotionType = MotionType.JOINT,
        speed: float = DEFAULT_SPEED_PERCENT,
    ) -> int:
        """Record where the arm is now (reads its pose and TCP position)."""
        pose, position = controller.get_pose(), controller.get_position()
        return self.record(pose, position, after=after, name=name, motion=motion, speed=speed)

    def add_waypoint(self, pose: Pose, position: Position, name: str | None = None) -> str:
        """A waypoint in the table that no step uses yet (e.g. a pallet corner); returns its name."""
        with self._lock:
            waypoint = Waypoint(
                name=self._unique_name(name or self.next_waypoint_name()), pose=pose, position=position
            )
            self._edit(self._program.steps, (*self._program.waypoints, waypoint))
            return waypoint.name

    def rename(self, index: int, name: str) -> None:
        """Rename the waypoint the move at line `index` goes to; every step using it follows."""
        with self._lock:
            self.rename_waypoint(self._move(index).waypoint, name)

    def rename_waypoint(self, old: str, new: str) -> None:
        with self._lock:
            if new.strip() == old:
                return
            clean = self._unique_name(new)
            waypoints = tuple(
                w.model_copy(update={"name": clean}) if w.name == old else w for w in self._program.waypoints
            )
            self._edit(_renamed(self._program.steps, old, clean), waypoints)

    def set_motion(self, index: int, motion: MotionType, speed: float) -> None:
        with self._lock:
            move = self._move(index)
            self.replace_step(index, move.model_copy(update={"motion": motion, "speed": speed}))

    def reteach(self, index: int, pose: Pose, position: Position) -> None:
        """Overwrite the waypoint of the move at line `index`: every move to it goes to the new place."""
        with self._lock:
            self.reteach_waypoint(self._move(index).waypoint, pose, position)

    def reteach_waypoint(self, name: str, pose: Pose, position: Position) -> None:
        with self._lock:
            waypoints = tuple(
                Waypoint(name=name, pose=pose, position=position) if w.name == name else w
                for w in self._program.waypoints
            )
            self._edit(self._program.steps, waypoints)

    def reteach_from(self, controller: Controller, index: int) -> None:
        self.reteach(index, controller.get_pose(), controller.get_position())

    def delete_waypoint(self, name: str) -> None:
        with self._lock:
            uses = self._program.uses_of(name)
            if uses:
                raise EditError(f"Waypoint {name!r} is used by {uses} step(s): delete or change them first")
            waypoints = tuple(w for w in self._program.waypoints if w.name != name)
            self._edit(self._program.steps, waypoints)

    def _unique_name(self, name: str) -> str:
        clean = name.strip()
        if not clean:
            raise EditError("A waypoint needs a name")
        if len(clean) > WAYPOINT_NAME_MAX:
            raise EditError(f"A waypoint name has at most {WAYPOINT_NAME_MAX} characters")
        if clean in set(self._program.waypoint_names()):
            raise EditError(f"A waypoint named {clean!r} already exists")
        return clean

    def _with_waypoint(
        self, waypoint: Waypoint, steps: tuple[Step, ...], path: tree.Path
    ) -> tuple[Waypoint, ...]:
        """The table with `waypoint` after the last waypoint used by a step listed before `path`."""
        before: list[str] = []
        for line in tree.lines(steps):
            if line.path == path:
                break
            before.extend(referenced_waypoints(line.step))
        table = list(self._program.waypoints)
        positions = [i for i, w in enumerate(table) if w.name in before]
        table.insert(max(positions) + 1 if positions else 0, waypoint)
        return tuple(table)


def _renamed(steps: tuple[Step, ...], old: str, new: str) -> tuple[Step, ...]:
    def one(step: Step) -> Step:
        updates: dict[str, object] = {name: _renamed(inner, old, new) for name, inner in children(step)}
        if isinstance(step, MoveStep) and step.waypoint == old:
            updates["waypoint"] = new
        if isinstance(step, PalletStep):
            updates["corners"] = tuple(new if c == old else c for c in step.corners)
        return step.model_copy(update=updates) if updates else step

    return tuple(one(step) for step in steps)
