"""Program files: a folder of versioned JSON documents, written atomically, read with clear refusals.

A write goes to a temporary file in the same folder, is fsynced, renamed over the target and the folder is
fsynced, so a crash or a kill leaves either the old file or the new one, never half of one.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import re
import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import TypeVar, cast

from pydantic import ValidationError

from pendant.paths import programs_dir
from pendant.program import gentle_json
from pendant.program.migrate import migrate
from pendant.program.models import PROGRAM_NAME_MAX, SCHEMA_VERSION, Program, describe_problems

SUFFIX = ".json"
AUTOSAVE_FILE = ".autosave.json"  # a dot file: never listed as a program
AUTOSAVE_REFUSED_PREFIX = ".autosave.refused."  # + UTC time + ".json": every refused autosave is kept
NAME_MAX = PROGRAM_NAME_MAX
_NAME_OK = re.compile(r"[A-Za-z0-9 _.\-]+")
MAX_FILE_BYTES = 5_000_000  # a program of thousands of steps is ~1 MB; anything bigger is not a program

log = logging.getLogger(__name__)


class ProgramFileError(Exception):
    """A file the pendant refuses (bad name, not JSON, not a program, newer schema); `str()` says why."""


def sanitize_name(name: str) -> str:
    """A program name safe to use as a file name in the programs folder (no path, no dot file).

    Strips a trailing ".json"; raises ProgramFileError for names that would leave the folder or hide.
    """
    cleaned = name.strip()
    if cleaned.lower().endswith(SUFFIX):
        cleaned = cleaned[: -len(SUFFIX)].strip()
    if not cleaned:
        raise ProgramFileError("A program needs a name")
    if len(cleaned) > NAME_MAX:
        raise ProgramFileError(f"A program name is at most {NAME_MAX} characters")
    if not _NAME_OK.fullmatch(cleaned) or cleaned.startswith("."):
        raise ProgramFileError(
            f"{name!r} is not a usable program name: use letters, digits, spaces, '_', '-' and '.' "
            "(not first)"
        )
    return cleaned


def parse_program(data: bytes, source: str) -> Program:
    """The program in `data`, or ProgramFileError saying why `source` is refused."""
    if len(data) > MAX_FILE_BYTES:
        raise ProgramFileError(f"{source} is too big to be a program ({len(data)} bytes)")
    if not gentle_json.is_big(data):
        return _parsed(data, source)
    # A big document's hundreds of thousands of objects must be gone before the collector is back on: a
    # collection that finds them alive moves them to the older generations, and a few readings later a full
    # collection walks the whole heap while every thread waits (229-277 ms, benchmarks/program_files.py).
    # A refusal keeps only its message: the error it came from holds the document's objects as its input.
    with gentle_json.collector_off():
        try:
            return _parsed(data, source)
        except ProgramFileError as error:
            reason = str(error)
    raise ProgramFileError(reason)


def _parsed(data: bytes, source: str) -> Program:
    try:
        document = gentle_json.loads(data)  # a big file a bit at a time: a Freeze never waits behind it
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ProgramFileError(f"{source} is not a JSON document: {error}") from error
    except RecursionError as error:
        raise ProgramFileError(f"{source} nests too deeply to be a program") from error
    if not isinstance(document, dict):
        raise ProgramFileError(f"{source} is not a program (expected a JSON object)")
    version = document.get("schema_version")
    if not isinstance(version, int) or isinstance(version, bool):
        raise ProgramFileError(f"{source} is not a program file (no schema_version)")
    if version < 1:
        raise ProgramFileError(
            f"{source} has schema version {version}, which no pendant writes (versions start at 1): "
            "the file is damaged or not a program file"
        )
    if version > SCHEMA_VERSION:
        raise ProgramFileError(
            f"{source} was written by a newer pendant (schema version {version}; this pendant reads up to "
            f"{SCHEMA_VERSION}). Update the pendant to open it."
        )
    try:
        return Program.model_validate(migrate(document))
    except ValidationError as error:
        raise ProgramFileError(f"{source} is not a valid program: {describe_problems(error)}") from error
    except RecursionError as error:
        raise ProgramFileError(f"{source} nests too deeply to be a program") from error


_Json = TypeVar("_Json")
FLOAT_DECIMALS = 9  # nanometres and nano-radians: a recorded 0 is written 0.0, not -9.5e-15


def rounded(value: _Json) -> _Json:
    """`value` (plain JSON data) with its floats rounded: the same shape, so the same type."""
    return cast(_Json, _rounded(value))


def _rounded(value: object) -> object:
    if isinstance(value, float):
        return round(value, FLOAT_DECIMALS) + 0.0  # + 0.0: no "-0.0" either
    if isinstance(value, dict):
        return {key: _rounded(item) for key, item in value.items()}
    if isinstance(value, list):
        return [_rounded(item) for item in value]
    return value


def program_document(program: Program) -> dict[str, object]:
    """The program as the plain JSON document a file holds (floats without noise)."""
    return rounded(program.model_dump(mode="json"))


def dump_program(program: Program) -> bytes:
    return (json.dumps(program_document(program), indent=2, ensure_ascii=False) + "\n").encode()


def atomic_write(path: Path, data: bytes) -> None:
    """Replace `path` with `data` so that a crash at any moment leaves the old or the new content."""
    folder = path.parent
    folder.mkdir(parents=True, exist_ok=True)
    fd, temp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as temp:
            temp.write(data)
            temp.flush()
            os.fsync(temp.fileno())
        os.replace(temp_name, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temp_name)
        raise
    _fsync_dir(folder)


def _fsync_dir(folder: Path) -> None:
    # The rename is only durable once the folder's entry is on disk (POSIX); Windows cannot open folders.
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


class ProgramStore:
    """The programs folder: list, load, save, delete by name; the autosave of the program being edited."""

    def __init__(self, folder: Path | str | None = None) -> None:
        self.folder = programs_dir() if folder is None else Path(folder)
        # Set by restore(): why the autosave was refused, for the page to show (None: nothing to say).
        self.restore_problem: str | None = None

    def path_of(self, name: str) -> Path:
        return self.folder / f"{sanitize_name(name)}{SUFFIX}"

    def names(self) -> list[str]:
        """Saved programs, sorted (dot files such as the autosave are not programs)."""
        if not self.folder.is_dir():
            return []
        return sorted(
            p.name[: -len(SUFFIX)]
            for p in self.folder.iterdir()
            if p.is_file() and p.name.endswith(SUFFIX) and not p.name.startswith(".")
        )

    def exists(self, name: str) -> bool:
        return self.path_of(name).is_file()

    def load(self, name: str) -> Program:
        path = self.path_of(name)
        try:
            data = path.read_bytes()
        except FileNotFoundError as error:
            raise ProgramFileError(f"No program named {sanitize_name(name)!r}") from error
        return parse_program(data, path.name).model_copy(update={"name": sanitize_name(name)})

    def save(self, program: Program, name: str) -> Program:
        """Write `program` as `name` (replacing it); returns the program as the file now holds it."""
        clean = sanitize_name(name)
        named = program.model_copy(update={"name": clean, "schema_version": SCHEMA_VERSION})
        data = dump_program(named)
        if len(data) > MAX_FILE_BYTES:  # never save what parse_program would refuse to load back
            raise ProgramFileError(
                f"This program is too big to save ({len(data)} bytes, at most {MAX_FILE_BYTES})"
            )
        atomic_write(self.path_of(clean), data)
        return Program.model_validate_json(data)

    def delete(self, name: str) -> None:
        path = self.path_of(name)
        try:
            path.unlink()
        except FileNotFoundError as error:
            raise ProgramFileError(f"No program named {sanitize_name(name)!r}") from error
        _fsync_dir(self.folder)

    # --- autosave: the program being edited, with the file it belongs to ---------------------------------
    @property
    def autosave_path(self) -> Path:
        return self.folder / AUTOSAVE_FILE

    def autosave(self, program: Program, file_name: str | None, dirty: bool) -> None:
        document = {"file_name": file_name, "dirty": dirty, "program": program_document(program)}
        atomic_write(self.autosave_path, (json.dumps(document, indent=2) + "\n").encode())

    def restore(self) -> tuple[Program, str | None, bool] | None:
        """The autosaved (program, file name, unsaved changes), or None when there is none to restore.

        An unreadable autosave is moved aside under a new timestamped name (never overwriting an earlier
        one) and `restore_problem` says what happened, for the page to show; it is None after a clean restore.
        """
        self.restore_problem = None
        try:
            data = self.autosave_path.read_bytes()
        except FileNotFoundError:
            return None
        except OSError as error:
            self.restore_problem = (
                f"The autosaved program could not be read ({error}); "
                "the pendant started with an empty program."
            )
            log.warning("%s", self.restore_problem)
            return None
        try:
            return _parse_autosave(data)
        except ProgramFileError as error:
            reason = str(error)
        try:
            kept = self._keep_refused_autosave()
        except OSError as error:
            # Left in place, so the first edit replaces it: say so, the operator may want to copy it first.
            self.restore_problem = (
                f"The autosaved program could not be restored: {reason}. "
                f"It could not be moved aside ({error}) and will be overwritten by the next edit: "
                f"copy {self.autosave_path} now to keep it. "
                "The pendant started with an empty program."
            )
        else:
            self.restore_problem = (
                f"The autosaved program could not be restored: {reason}. The file was kept as {kept}; "
                "the pendant started with an empty program."
            )
        log.warning("%s", self.restore_problem)
        return None

    def _keep_refused_autosave(self) -> Path:
        """Move the autosave to a free `.autosave.refused.<UTC time>[-n].json`; returns where it went."""
        stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
        for n in range(1, 1000):
            suffix = "" if n == 1 else f"-{n}"
            kept = self.folder / f"{AUTOSAVE_REFUSED_PREFIX}{stamp}{suffix}{SUFFIX}"
            try:
                # A hard link fails if the name is taken, so an earlier refused autosave is never replaced.
                os.link(self.autosave_path, kept)
            except FileExistsError:
                continue
            except OSError:
                # No hard links on this filesystem: a checked rename (racy only against another pendant).
                if kept.exists():
                    continue
                os.rename(self.autosave_path, kept)
            else:
                os.unlink(self.autosave_path)
            _fsync_dir(self.folder)
            return kept
        raise OSError(f"too many refused autosaves named {AUTOSAVE_REFUSED_PREFIX}{stamp}*")


def _parse_autosave(data: bytes) -> tuple[Program, str | None, bool]:
    """(program, file name, dirty) from an autosave document, or ProgramFileError saying why not."""
    try:
        document = json.loads(data)
    except (UnicodeDecodeError, json.JSONDecodeError) as error:
        raise ProgramFileError(f"{AUTOSAVE_FILE} is not a JSON document: {error}") from error
    if not isinstance(document, dict) or not isinstance(document.get("program"), dict):
        raise ProgramFileError(f"{AUTOSAVE_FILE} is not an autosave (no program in it)")
    program = parse_program(json.dumps(document["program"]).encode(), AUTOSAVE_FILE)
    file_name = document.get("file_name")
    return program, file_name if isinstance(file_name, str) else None, bool(document.get("dirty"))
