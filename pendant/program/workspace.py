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
from typing import NamedTuple

from pendant.controller import Controller
from pendant.program.editing import EditError, ProgramEditing
from pendant.program.export import export_script
from pendant.program.files import ProgramFileError, ProgramStore, dump_program, parse_program, sanitize_name
from pendant.program.models import Program
from pendant.program.motion import PathPlanner
from pendant.program.run_views import RunViews
from pendant.program.runner import ProgramRunner, RunProgress, RunState
from pendant.program.versions import VersionedStore

log = logging.getLogger(__name__)

UNTITLED = "untitled"


class Change(StrEnum):
    PROGRAM = "program"  # steps or name changed
    FILES = "files"  # the folder's list of programs, or the current file name / saved state
    RUN = "run"  # the runner's progress


UNDO_DEPTH = 200


class _Snapshot(NamedTuple):
    program: Program
    file_name: str | None
    dirty: bool


ChangeListener = Callable[[Change], None]


class ProgramWorkspace(ProgramEditing):
    """One per pendant: the current program, its file, the programs folder and the runner; the edits are
    ProgramEditing's, each one undoable."""

    def __init__(self, store: ProgramStore, runner: ProgramRunner) -> None:
        self.store = store
        self.runner = runner
        self._lock = threading.RLock()
        self._listeners: list[ChangeListener] = []
        self._undo: list[_Snapshot] = []
        self._redo: list[_Snapshot] = []
        self.supervisor: int | None = None  # the browser that started the run (see start_run)
        self.path_recordings: Path | None = None  # where path recordings are kept (Path steps name theirs)
        if runner.load is None:  # Call steps open the programs of this folder
            runner.load = store.load
        restored = store.restore()
        if restored is not None:
            self._program, self._file_name, self._dirty = restored
            steps = len(self._program.steps)
            log.info("restored the autosaved program %r (%d steps)", self._program.name, steps)
        else:
            self._program, self._file_name, self._dirty = Program(), None, False
        # The run's progress reaches the views without the run waiting for them (run_views.py).
        runner.add_listener(RunViews(lambda: self._notify(Change.RUN)).changed)

    @classmethod
    def for_controller(
        cls, controller: Controller, folder: str | Path | None = None, planner: PathPlanner | None = None
    ) -> ProgramWorkspace:
        """The workspace a pendant creates once: programs in `folder` (default: $PENDANT_PROGRAMS_DIR, else
        ./programs) with their git history, runs on the real clock; `planner` plans planned Move J steps."""
        return cls(VersionedStore(folder), ProgramRunner(controller, planner=planner))

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

    # --- editing (pendant.program.editing), undo and redo --------------------------------------------
    def _commit(self, program: Program) -> None:
        """Apply an edit: on disk before it is applied or shown (a failed autosave refuses it whole)."""
        with self._lock:
            self.store.autosave(program, self._file_name, True)
            self._undo.append(self._snapshot())
            del self._undo[:-UNDO_DEPTH]
            self._redo.clear()
            self._program, self._dirty = program, True
        self._notify(Change.PROGRAM)

    def _snapshot(self) -> _Snapshot:
        return _Snapshot(self._program, self._file_name, self._dirty)

    def _restore(self, snapshot: _Snapshot) -> None:
        self.store.autosave(snapshot.program, snapshot.file_name, snapshot.dirty)
        self._program, self._file_name, self._dirty = snapshot
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    def undo(self) -> None:
        """Take back the last edit (also New, Load and Upload: the program they replaced comes back)."""
        with self._lock:
            if not self._undo:
                raise EditError("Nothing to undo")
            self._redo.append(self._snapshot())
            self._restore(self._undo.pop())

    def redo(self) -> None:
        with self._lock:
            if not self._redo:
                raise EditError("Nothing to redo")
            self._undo.append(self._snapshot())
            self._restore(self._redo.pop())

    def _replace_program(self, program: Program, file_name: str | None, dirty: bool) -> None:
        """New, Load, Upload: the program on screen is replaced, undoably."""
        with self._lock:
            self.store.autosave(program, file_name, dirty)
            self._undo.append(self._snapshot())
            del self._undo[:-UNDO_DEPTH]
            self._redo.clear()
            self._program, self._file_name, self._dirty = program, file_name, dirty
        self._notify(Change.PROGRAM)
        self._notify(Change.FILES)

    def _autosave(self) -> None:
        # Before anyone is told of the change: once the page shows a waypoint, it is on disk.
        self.store.autosave(self._program, self._file_name, self._dirty)

    # --- files -------------------------------------------------------------------------------------
    def saved_programs(self) -> list[str]:
        return self.store.names()

    def new(self) -> None:
        """Start an empty program (the previous one stays in its file if it was saved)."""
        self._replace_program(Program(), None, False)

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

    @property
    def versions(self) -> VersionedStore:
        """The programs folder's history (pendant.program.versions)."""
        if not isinstance(self.store, VersionedStore):
            raise ProgramFileError("This programs folder keeps no history")
        return self.store

    def restore_version(self, revision: str) -> None:
        """Bring back version `revision` of the current file, as a new version; Undo gives back the program
        that was on screen (as unsaved changes: the file now holds the restored version)."""
        with self._lock:
            if self._file_name is None:
                raise ProgramFileError("This program has no file yet: there are no versions to restore")
            program = self.versions.restore_version(self._file_name, revision)
            self._replace_program(program, program.name, False)
            self._undo[-1] = self._undo[-1]._replace(dirty=True)

    def load(self, name: str) -> None:
        """Open a saved program; a refused file leaves the current program (and every file) as it was."""
        program = self.store.load(name)
        self._replace_program(program, program.name, False)

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
        """Open a program sent from the browser; it becomes the current (unsaved) program, keeping the
        `name` it carries (the file name when it has none). A refused upload raises ProgramFileError and
        changes nothing."""
        self.open_uploaded(self.read_upload(filename, data))

    def read_upload(self, filename: str, data: bytes) -> Program:
        """The program in an uploaded file (ProgramFileError if refused), not opened yet."""
        program = parse_program(data, filename)
        if "name" not in program.model_fields_set:
            try:
                name = sanitize_name(filename.rsplit("/", 1)[-1].rsplit("\\", 1)[-1])
            except ProgramFileError:
                name = UNTITLED
            program = program.model_copy(update={"name": name})
        return program

    def open_uploaded(self, program: Program) -> None:
        self._replace_program(program, None, True)

    def download(self) -> tuple[str, bytes]:
        """(file name, JSON bytes) of the current program, for the browser to save."""
        program = self._program
        return f"{program.name}.json", dump_program(program)

    def export(self) -> tuple[str, bytes]:
        """(file name, Python source) of the current program as a standalone script."""
        program = self._program
        stem = re.sub(r"\W+", "_", program.name).strip("_") or "program"
        return f"{stem}.py", export_script(program, self.store.load).encode()

    # --- running -----------------------------------------------------------------------------------
    # `supervisor`: the browser (viser client id) that started or continued the run; the page pauses the
    # run when that browser goes away (None: a headless start, tied to no page).
    def start_run(self, loops: int = 1, *, start_line: int = 0, supervisor: int | None = None) -> None:
        """Run the program on the worker thread (from line `start_line`: Run from the selected step)."""
        program = self._program
        self._start(lambda: self.runner.run(program, loops, start_line=start_line), supervisor)

    def start_step(self, supervisor: int | None = None) -> None:
        program = self._program
        self._start(lambda: self.runner.step(program), supervisor)

    def start_resume(self, supervisor: int | None = None) -> None:
        """Continue a paused run, or a failed or stopped one at the step it ended on."""
        self._start(self.runner.resume, supervisor)

    def start_skip(self, supervisor: int | None = None) -> None:
        """Continue a failed or stopped run at the step after that one."""
        self._start(self.runner.skip, supervisor)

    def _start(self, command: Callable[[], RunProgress], supervisor: int | None) -> None:
        self.runner.start(command)
        self.supervisor = supervisor

    def supervisor_left(self, client_id: int, who: str) -> bool:
        """The browser supervising a run went away: pause the run (the arm held, the place kept)."""
        if self.supervisor != client_id or self.runner.progress.state is not RunState.RUNNING:
            return False
        self.runner.pause(because=f"{who}'s page closed while the program ran")
        return True

    def pause(self) -> None:
        self.runner.pause()

    def stop(self, cause: str = "") -> None:
        self.runner.stop(cause)

    def request_stop(self, cause: str) -> None:
        self.runner.request_stop(cause)
