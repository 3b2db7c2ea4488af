"""The program being taught, shared by every browser watching the pendant: edits, files, runs, autosave.

Panels are views: they call these methods and redraw when `on_change` fires. Every edit is autosaved at once
(atomically), so a crash or a kill never loses a recorded waypoint; on start the autosave is restored.
"""

from __future__ import annotations

import logging
import re
import threading
from collections.abc import Callable
from enum import StrEnum
from pathlib import Path

from pydantic import ValidationError

from pendant.controller import Controller, Pose, Position
from pendant.controller.types import MotionType
from pendant.program.export import export_script
from pendant.program.files import ProgramFileError, ProgramStore, dump_program, parse_program, sanitize_name
from pendant.program.models import (
    DEFAULT_SPEED_PERCENT,
    WAYPOINT_NAME_MAX,
    MoveStep,
    Program,
    Step,
    Waypoint,
    describe_problems,
)
from pendant.program.runner import ProgramRunner, RunProgress

log = logging.getLogger(__name__)

UNTITLED = "untitled"


class Change(StrEnum):
    PROGRAM = "program"  # steps or name changed
    FILES = "files"  # the folder's list of programs, or the current file name / saved state
    RUN = "run"  # the runner's progress


class EditError(Exception):
    """An edit the workspace refuses (bad index, duplicate waypoint name); `str()` says why."""


ChangeListener = Callable[[Change], None]


class ProgramWorkspace:
    """One per pendant: the current program, its file, the programs folder and the runner."""

    def __init__(self, store: ProgramStore, runner: ProgramRunner) -> None:
        self.store = store
        self.runner = runner
        self._lock = threading.RLock()
        self._listeners: list[ChangeListener] = []
        restored = store.restore()
        if restored is not None:
            self._program, self._file_name, self._dirty = restored
            steps = len(self._program.steps)
            log.info("restored the autosaved program %r (%d steps)", self._program.name, steps)
        else:
            self._program, self._file_name, self._dirty = Program(), None, False
        runner.add_listener(lambda _: self._notify(Change.RUN))

    @classmethod
    def for_controller(cls, controller: Controller, folder: str | Path | None = None) -> ProgramWorkspace:
        """The workspace a pendant creates once: programs in `folder` (default: $PENDANT_PROGRAMS_DIR, else
        ./programs), runs on the real clock."""
        return cls(ProgramStore(folder), ProgramRunner(controller))

    # --- observing ---------------------------------------------------------------------------------
    @property
    def program(self) -> Program:
        return self._program

    @property
    def file_name(self) -> str | None:
        """The program file this program was loaded from or saved to; None for a new one."""
        return self._file_name

    @property
    def dirty(self) -> bool:
        """Changes not yet saved to `file_name` (they are in the autosave)."""
        return self._dirty

    @property
    def progress(self) -> RunProgress:
        return self.runner.progress

    def on_change(self, listener: ChangeListener) -> None:
        self._listeners.append(listener)

    def remove_listener(self, listener: ChangeListener) -> None:
        if listener in self._listeners:
            self._listeners.remove(listener)

    def _notify(self, change: Change) -> None:
        for listener in list(self._listeners):
            try:
                listener(change)
            except Exception:  # one broken view must not break editing for the others
                log.exception("program workspace listener failed")

    # --- editing -----------------------------------------------------------------------------------
    def _edit(self, steps: list[Step] | tuple[Step, ...]) -> None:
        with self._lock:
            try:  # validated whole, as a load would: an edit never saves what could not be read back
                program = Program.model_validate({**dict(self._program), "steps": tuple(steps)})
            except ValidationError as error:
                raise EditError(describe_problems(error, limit=1)) from error
            # On disk before it is applied or shown: if the autosave fails, the edit is refused whole.
            self.store.autosave(program, self._file_name, True)
            self._program, self._dirty = program, True
        self._notify(Change.PROGRAM)

    def _autosave(self) -> None:
        # Before anyone is told of the change: once the page shows a waypoint, it is on disk.
        self.store.autosave(self._program, self._file_name, self._dirty)

    def _index(self, index: int) -> int:
        if not 0 <= index < len(self._program.steps):
            raise EditError(f"There is no step {index + 1}")
        return index

    def _move(self, index: int) -> MoveStep:
        step = self._program.steps[self._index(index)]
        if not isinstance(step, MoveStep):
            raise EditError(f"Step {index + 1} is not a move")
        return step

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
        """Add a move to a new waypoint (after step `after`, else at the end); returns its index."""
        with self._lock:
            waypoint = Waypoint(
                name=self._unique_name(name or self.next_waypoint_name()), pose=pose, position=position
            )
            return self.insert_step(MoveStep(waypoint=waypoint, motion=motion, speed=speed), after=after)

    def record_from(self, controller: Controller, *, after: int | None = None, **options: object) -> int:
        """Record where the arm is now (reads its pose and TCP position)."""
        pose, position = controller.get_pose(), controller.get_position()
        return self.record(pose, position, after=after, **options)  # type: ignore[arg-type]

    def insert_step(self, step: Step, *, after: int | None = None) -> int:
        with self._lock:
            steps = list(self._program.steps)
            index = len(steps) if after is None else self._index(after) + 1
            steps.insert(index, step)
            self._edit(steps)
            return index

    def replace_step(self, index: int, step: Step) -> None:
        with self._lock:
            old = self._program.steps[self._index(index)]
            if isinstance(step, MoveStep) and (
                not isinstance(old, MoveStep) or old.waypoint.name != step.waypoint.name
            ):
                self._unique_name(step.waypoint.name)
            steps = list(self._program.steps)
            steps[index] = step
            self._edit(steps)

    def rename(self, index: int, name: str) -> None:
        with self._lock:
            move = self._move(index)
            if name.strip() == move.waypoint.name:
                return
            waypoint = Waypoint(
                name=self._unique_name(name), pose=move.waypoint.pose, position=move.waypoint.position
            )
            self.replace_step(index, move.model_copy(update={"waypoint": waypoint}))

    def set_motion(self, index: int, motion: MotionType, speed: float) -> None:
        with self._lock:
            move = self._move(index)
            self.replace_step(index, MoveStep(waypoint=move.waypoint, motion=motion, speed=speed))

    def reteach(self, index: int, pose: Pose, position: Position) -> None:
        """Overwrite step `index`'s waypoint with a new pose and position, keeping its name."""
        with self._lock:
            move = self._move(index)
            waypoint = Waypoint(name=move.waypoint.name, pose=pose, position=position)
            self.replace_step(index, move.model_copy(update={"waypoint": waypoint}))

    def reteach_from(self, controller: Controller, index: int) -> None:
        self.reteach(index, controller.get_pose(), controller.get_position())

    def delete_step(self, index: int) -> None:
        with self._lock:
            steps = list(self._program.steps)
            del steps[self._index(index)]
            self._edit(steps)

    def move_step(self, index: int, delta: int) -> int:
        """Move step `index` up (delta -1) or down (+1); returns where it is now."""
        with self._lock:
            steps = list(self._program.steps)
            self._index(index)
            to = min(max(index + delta, 0), len(steps) - 1)
            if to != index:
                steps.insert(to, steps.pop(index))
                self._edit(steps)
            return to

    def duplicate_step(self, index: int) -> int:
        """A copy right after step `index` (a move gets a new waypoint name): e.g. approach and retreat."""
        with self._lock:
            step = self._program.steps[self._index(index)]
            if isinstance(step, MoveStep):
                names = set(self._program.waypoint_names())
                room = WAYPOINT_NAME_MAX - len(f" {len(names) + 1}")  # for the " k" that keeps it unique
                base = f"{step.waypoint.name} copy"[:room].rstrip()
                name = next(
                    n
                    for k in range(1, len(names) + 2)
                    if (n := base if k == 1 else f"{base} {k}") not in names
                )
                step = step.model_copy(update={"waypoint": step.waypoint.model_copy(update={"name": name})})
            return self.insert_step(step, after=index)

    def _unique_name(self, name: str) -> str:
        clean = name.strip()
        if not clean:
            raise EditError("A waypoint needs a name")
        if len(clean) > WAYPOINT_NAME_MAX:
            raise EditError(f"A waypoint name has at most {WAYPOINT_NAME_MAX} characters")
        names = set(self._program.waypoint_names())
        if clean not in names:
            return clean
        raise EditError(f"A waypoint named {clean!r} already exists")

    # --- files -------------------------------------------------------------------------------------
    def saved_programs(self) -> list[str]:
        return self.store.names()

    def new(self) -> None:
        """Start an empty program (the previous one stays in its file if it was saved)."""
        with self._lock:
            self._program, self._file_name, self._dirty = Program(), None, False
            self._autosave()
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)

    def save(self) -> str:
        """Save to the current file; a new program needs `save_as`."""
        with self._lock:
            if self._file_name is None:
                raise ProgramFileError("This program has no file yet: use Save as")
            return self._save_to(self._file_name)

    def save_as(self, name: str, *, overwrite: bool = False) -> str:
        """Save under a new name; an existing different file is not replaced unless `overwrite`."""
        with self._lock:
            clean = sanitize_name(name)
            if not overwrite and clean != self._file_name and self.store.exists(clean):
                raise ProgramFileError(f"A program named {clean!r} already exists: pick another name")
            return self._save_to(clean)

    def _save_to(self, name: str) -> str:
        self._program = self.store.save(self._program, name)
        self._file_name, self._dirty = self._program.name, False
        self._autosave()
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)
        return self._program.name

    def load(self, name: str) -> None:
        """Open a saved program; a refused file leaves the current program (and every file) as it was."""
        program = self.store.load(name)
        with self._lock:
            self._program, self._file_name, self._dirty = program, program.name, False
            self._autosave()
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)

    def delete_file(self, name: str) -> None:
        """Delete a saved program; the program on screen stays (as unsaved) if it was that file."""
        clean = sanitize_name(name)
        self.store.delete(clean)
        with self._lock:
            if self._file_name == clean:
                self._file_name, self._dirty = None, True
                self._autosave()
        self._notify(Change.FILES)

    def upload(self, filename: str, data: bytes) -> None:
        """Open a program sent from the browser; it becomes the current (unsaved) program.

        A refused upload raises ProgramFileError and changes nothing."""
        try:
            name = sanitize_name(filename.rsplit("/", 1)[-1].rsplit("\\", 1)[-1])
        except ProgramFileError:
            name = UNTITLED
        program = parse_program(data, filename)
        with self._lock:
            self._program = program.model_copy(update={"name": name})
            self._file_name, self._dirty = None, True
            self._autosave()
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)

    def download(self) -> tuple[str, bytes]:
        """(file name, JSON bytes) of the current program, for the browser to save."""
        program = self._program
        return f"{program.name}.json", dump_program(program)

    def export(self) -> tuple[str, bytes]:
        """(file name, Python source) of the current program as a standalone script."""
        program = self._program
        stem = re.sub(r"\W+", "_", program.name).strip("_") or "program"
        return f"{stem}.py", export_script(program).encode()

    # --- running -----------------------------------------------------------------------------------
    def start_run(self, loops: int = 1) -> None:
        program = self._program
        self.runner.start(lambda: self.runner.run(program, loops))

    def start_step(self) -> None:
        program = self._program
        self.runner.start(lambda: self.runner.step(program))

    def start_resume(self) -> None:
        self.runner.start(self.runner.resume)

    def pause(self) -> None:
        self.runner.pause()

    def stop(self) -> None:
        self.runner.stop()
