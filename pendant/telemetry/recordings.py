"""The folder of finished recordings: `<data>/recordings/pendant-YYYYmmdd-HHMMSS.{mcap,csv}`, newest first,
at most MAX_KEPT of them (the oldest are deleted when a new one starts)."""

from __future__ import annotations

import datetime as dt
import re
from dataclasses import dataclass
from pathlib import Path

MAX_KEPT = 50
PREFIX = "pendant-"
SUFFIXES = (".mcap", ".csv")


class RecordingError(Exception):
    """A recording cannot be written where it must go; the message says where, why and what to do."""


class RecordingRefused(Exception):
    """A recording cannot start or stop as asked (a bad or taken name, one already running, none running);
    `status` is the HTTP answer that says so (400 or 409)."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


# A name a script gives a recording: a file name on any system, no path, no hidden file.
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")


def named_stem(folder: Path, name: str) -> str:
    """`pendant-<name>`, refused (400) when `name` is not a plain file name, (409) when it is taken."""
    if not NAME.fullmatch(name) or name.endswith(SUFFIXES):
        raise RecordingRefused(
            400,
            f"Bad recording name {name[:80]!r}: 1 to 64 letters, digits, '-', '_' or '.', starting with a "
            "letter or digit, no file suffix",
        )
    stem = PREFIX + name
    if any((folder / f"{stem}{s}").exists() for s in SUFFIXES):
        raise RecordingRefused(409, f"A recording named {name!r} already exists: choose another name")
    return stem


def name_of(stem: str) -> str:
    """The name a recording goes by (the Dashboard's and the API's): its stem without the prefix."""
    return stem.removeprefix(PREFIX)


def recordings_dir(data_dir: str | Path) -> Path:
    """`<data>/recordings` (created by the first recording: a read-only data folder must not stop the
    pendant from starting)."""
    return Path(data_dir) / "recordings"


@dataclass(frozen=True)
class Recording:
    stem: str  # pendant-20261122-221500
    files: tuple[Path, ...]  # the .mcap and .csv that exist

    @property
    def label(self) -> str:
        size_kb = sum(f.stat().st_size for f in self.files if f.exists()) / 1024
        return f"{self.stem.removeprefix(PREFIX)} ({size_kb:.0f} kB)"


def new_stem(folder: Path, wall_time: float) -> str:
    stem = PREFIX + dt.datetime.fromtimestamp(wall_time).strftime("%Y%m%d-%H%M%S")
    n = 1
    candidate = stem
    while any((folder / f"{candidate}{s}").exists() for s in SUFFIXES):
        n += 1
        candidate = f"{stem}-{n}"
    return candidate


def list_recordings(folder: Path) -> list[Recording]:
    """Finished and running recordings in the folder, newest first."""
    stems = sorted({p.stem for p in folder.glob(f"{PREFIX}*") if p.suffix in SUFFIXES}, reverse=True)
    return [
        Recording(stem, tuple(folder / f"{stem}{s}" for s in SUFFIXES if (folder / f"{stem}{s}").exists()))
        for stem in stems
    ]


def prune(folder: Path, keep: int = MAX_KEPT) -> None:
    for recording in list_recordings(folder)[keep:]:
        for path in recording.files:
            path.unlink(missing_ok=True)
