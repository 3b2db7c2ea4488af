"""The folder of finished recordings: `<data>/recordings/pendant-YYYYmmdd-HHMMSS.{mcap,csv}`, newest first,
at most MAX_KEPT of them (the oldest are deleted when a new one starts)."""

from __future__ import annotations

import datetime as dt
from dataclasses import dataclass
from pathlib import Path

MAX_KEPT = 50
PREFIX = "pendant-"
SUFFIXES = (".mcap", ".csv")


class RecordingError(Exception):
    """A recording cannot be written where it must go; the message says where, why and what to do."""


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
