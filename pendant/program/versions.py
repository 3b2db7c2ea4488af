"""A programs folder whose every save, delete and restore is a version (a commit of its git history).

The file is always written first: a history that cannot be written (a damaged repository, a read-only .git)
never costs the save, it is said in `history_note`. A file changed behind the pendant's back is committed
as it was found before the pendant replaces or deletes it, so that version is never lost either.
"""

from __future__ import annotations

import contextlib
import errno
import getpass
import logging
from collections.abc import Callable, Iterator
from pathlib import Path

from pendant.program.diff import ProgramDiff, diff_programs
from pendant.program.files import (
    SUFFIX,
    ProgramFileError,
    ProgramStore,
    atomic_write,
    parse_program,
    sanitize_name,
)
from pendant.program.folder_lock import saving
from pendant.program.history import MAX_VERSIONS, OUTSIDE, HistoryError, ProgramHistory, Version
from pendant.program.models import Program

log = logging.getLogger(__name__)


def default_who() -> str:
    """Who saves when no page operator is known: the user running this process."""
    try:
        return f"{getpass.getuser()} (pendant)"
    except (KeyError, OSError):
        return "pendant"


def _not_written(what: str, file_name: str, folder: Path, error: OSError) -> str:
    reason = error.strerror or str(error)
    if error.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        reason += f": the programs folder {folder} is read-only for the pendant"
    return f"{file_name} could not be {what} ({reason}); nothing was changed"


class VersionedStore(ProgramStore):
    """A ProgramStore with a git history. `who()` names whoever is saving now, for the commit's author."""

    def __init__(self, folder: Path | str | None = None, who: Callable[[], str] = default_who) -> None:
        super().__init__(folder)
        self.history = ProgramHistory(self.folder)
        self.who = who
        # What the page should show about the last recorded change (a failure, a file changed outside the
        # pendant); None when it went as expected.
        self.history_note: str | None = None

    # --- writing: file first, then the commit ------------------------------------------------------------
    def save(self, program: Program, name: str) -> Program:
        with self._saving("saved", sanitize_name(name)):
            return self._save(program, sanitize_name(name))

    def delete(self, name: str) -> None:
        with self._saving("deleted", sanitize_name(name)):
            self._delete(sanitize_name(name))

    def restore_version(self, name: str, revision: str) -> Program:
        """Write back version `revision` of program `name` byte for byte, as a new version."""
        with self._saving("restored", sanitize_name(name)):
            return self._restore_version(sanitize_name(name), revision)

    @contextlib.contextmanager
    def _saving(self, what: str, clean: str) -> Iterator[None]:
        """One save of this folder at a time, across processes: the file and its commit go together."""
        with contextlib.ExitStack() as stack:
            try:
                stack.enter_context(saving(self.folder))
            except OSError as error:
                raise ProgramFileError(_not_written(what, clean + SUFFIX, self.folder, error)) from error
            yield

    def _save(self, program: Program, clean: str) -> Program:
        file_name = clean + SUFFIX
        self.history_note = None
        previous = self._committed_program(file_name)
        try:
            saved = super().save(program, clean)
        except OSError as error:
            raise ProgramFileError(_not_written("saved", file_name, self.folder, error)) from error
        if previous is None:
            summary = f"new program, {len(saved.steps)} steps, {len(saved.waypoints)} waypoints"
            body: tuple[str, ...] = ()
        else:
            change = diff_programs(previous, saved)
            summary, body = change.summary(), change.lines
        self._record(file_name, f"Save {clean}: {summary}", body)
        return saved

    def _delete(self, clean: str) -> None:
        self.history_note = None
        if self.exists(clean):
            self._committed_program(clean + SUFFIX)  # a hand-edited file is kept before it goes
        try:
            super().delete(clean)
        except OSError as error:
            raise ProgramFileError(_not_written("deleted", clean + SUFFIX, self.folder, error)) from error
        self._record(clean + SUFFIX, f"Delete {clean}", ())

    def _restore_version(self, clean: str, revision: str) -> Program:
        file_name = clean + SUFFIX
        self.history_note = None
        version, data = self._read(file_name, revision)
        program = parse_program(data, f"{file_name} of version {version.short}")
        self._committed_program(file_name)
        try:
            atomic_write(self.folder / file_name, data)
        except OSError as error:
            raise ProgramFileError(_not_written("restored", file_name, self.folder, error)) from error
        when = version.time.strftime("%Y-%m-%d %H:%M")
        self._record(file_name, f"Restore {clean} to version {version.short} of {when} UTC", ())
        return program.model_copy(update={"name": clean})

    def _record(self, file_name: str, message: str, body: tuple[str, ...]) -> None:
        text = message + ("\n\n" + "\n".join(f"- {line}" for line in body) if body else "")
        try:
            self.history.record(file_name, text + f"\n\nBy: {self.who()}", self.who())
        except HistoryError as error:
            self._note(f"{file_name} was saved, but not recorded in the history: {error}")

    def _note(self, text: str) -> None:
        self.history_note = f"{self.history_note} {text}" if self.history_note else text
        log.warning("%s", text)

    def _committed_program(self, file_name: str) -> Program | None:
        """The newest version of `file_name` in the history (after committing the file as found in the
        folder if it differs: changed by hand, copied in), or None when there is no readable one."""
        path = self.folder / file_name
        try:
            found = path.read_bytes() if path.is_file() else None
            committed = self.history.committed_bytes(file_name)
            if found is not None and found != committed:
                message = f"{file_name} as found in the folder (changed {OUTSIDE})"
                if self.history.exists and committed is not None:
                    self._note(
                        f"{file_name} had been changed {OUTSIDE}; that version is kept in the history."
                    )
                self.history.record(file_name, message, OUTSIDE)
                committed = found
        except HistoryError as error:  # the commit that follows meets it too, and says so
            log.warning("the history of %s could not be read: %s", file_name, error)
            committed = None
        except OSError as error:
            self._note(f"{file_name} could not be read before it was replaced: {error}")
            committed = None
        if committed is None:
            return None
        try:
            return parse_program(committed, file_name)
        except ProgramFileError:
            return None  # the old one was not a program: the new one is described as new

    # --- reading -------------------------------------------------------------------------------------------
    def versions(self, name: str, limit: int = MAX_VERSIONS) -> list[Version]:
        return self.history.versions(sanitize_name(name) + SUFFIX, limit)

    def _read(self, file_name: str, revision: str) -> tuple[Version, bytes]:
        return self.history.read(file_name, revision)

    def version_bytes(self, name: str, revision: str) -> bytes:
        """Program `name` as version `revision` holds it, byte for byte."""
        return self._read(sanitize_name(name) + SUFFIX, revision)[1]

    def version_program(self, name: str, revision: str) -> Program:
        clean = sanitize_name(name)
        version, data = self._read(clean + SUFFIX, revision)
        return parse_program(data, f"{clean}{SUFFIX} of version {version.short}")

    def diff_versions(self, name: str, old: str, new: str) -> ProgramDiff:
        return diff_programs(self.version_program(name, old), self.version_program(name, new))
