"""Finishing a recording whose pendant died (kill -9, power cut): every record up to the last flushed chunk is
copied into a new, properly finished MCAP (the official `mcap` writer), and the CSV beside it is made from its
/motors channel. Run on start for the recordings folder.

Start-up never depends on what a file holds: it is read through mcap_scan (lengths checked against the file,
decompression capped, REPAIR_TIME_LIMIT_S per file), in a thread of its own while the pendant serves. A file
that is more than a cut-short recording (not an MCAP, damaged inside, too slow to read, nothing complete in
it) is moved to `recordings/damaged/` with its bytes unchanged; what could be read before the damage is kept
as the recording."""

from __future__ import annotations

import csv
import json
import logging
import os
import threading
from collections.abc import Callable
from pathlib import Path
from typing import IO

from mcap.records import Attachment, Channel, Message, Metadata, Schema
from mcap.writer import CompressionType, Writer

from pendant.telemetry.mcap_scan import MAGIC, Damaged, Truncated, records
from pendant.telemetry.recorder import CSV_FIELDS, N_MOTORS, csv_header
from pendant.telemetry.recordings import PREFIX

REPAIR_TIME_LIMIT_S = 120.0  # one file; a 10-minute recording (2.9 MB) takes 2.4 s of CPU, two hours ~30 s
DAMAGED = "damaged"  # the subfolder of recordings/ where unrepairable files go, bytes unchanged

log = logging.getLogger(__name__)


def finished(path: Path) -> bool:
    """An MCAP file ends with its magic bytes once its writer closed it."""
    size = path.stat().st_size
    if size < 2 * len(MAGIC):
        return False
    with path.open("rb") as stream:
        stream.seek(size - len(MAGIC))
        return stream.read() == MAGIC


def unfinished(folder: Path) -> list[Path]:
    """The recordings in `folder` whose writer did not finish them (a stat and 8 bytes read each)."""
    found = []
    for path in sorted(folder.glob(f"{PREFIX}*.mcap")):
        try:
            if not finished(path):
                found.append(path)
        except OSError as error:
            log.warning("recording %s cannot be read: %s", path, error)
    return found


def repair_all(folder: Path) -> list[str]:
    """Finish every unfinished recording in `folder`; one line per file for the event log."""
    return [repair_safely(path) for path in unfinished(folder)]


def repair_in_background(paths: list[Path], say: Callable[[str], object]) -> threading.Thread:
    """Repair `paths` one after the other in a thread of their own, `say`ing each one's line: start-up
    waits for none of them (a two-hour recording takes about 30 s of CPU to repair)."""

    def run() -> None:
        for path in paths:
            say(repair_safely(path))

    thread = threading.Thread(target=run, name="recording-repair", daemon=True)
    thread.start()
    return thread


def repair_safely(path: Path, time_limit_s: float = REPAIR_TIME_LIMIT_S) -> str:
    """repair(), and whatever goes wrong a line that says so (never an exception)."""
    try:
        note = repair(path, time_limit_s)
    except OSError as error:  # a read-only folder: the file stays as it is, readable up to its last flush
        note = f"Recording {path.stem} was not finished and could not be repaired ({error})"
    except Exception as error:  # nothing a file holds may stop the pendant
        log.exception("repairing %s", path)
        try:
            note = _move_aside(path, f"{type(error).__name__}: {error}", 0)
        except OSError as move_error:
            note = f"Recording {path.stem} could not be repaired ({error}) nor moved aside ({move_error})"
    return note


def repair(path: Path, time_limit_s: float = REPAIR_TIME_LIMIT_S) -> str:
    """Rewrite `path` with what it holds up to its last complete record (its CSV too, when missing), or move
    it to damaged/ when it is more than cut short; the line for the event log."""
    temporary = path.with_suffix(".mcap.tmp")
    csv_temporary = path.with_name(f".{path.stem}.csv.tmp")
    try:
        with temporary.open("wb") as out, csv_temporary.open("w", newline="") as csv_out:
            copy = _Copy(out, csv_out)
            damage: str | None = None
            with path.open("rb") as stream:
                try:
                    for record in records(stream, path.stat().st_size, time_limit_s):
                        copy.add(record)
                    # Its data section is whole: killed while it wrote the summary, which is written anew.
                except Truncated:
                    pass  # the unfinished chunk at the end: everything before it is kept
                except Damaged as error:
                    damage = str(error)
            copy.finish()
        if damage is None and copy.messages == 0:
            damage = "it ends before its first complete chunk"
        if damage is not None:
            note = _move_aside(path, damage, copy.messages)
        else:
            note = (
                f"Recording {path.stem} was not finished (the pendant stopped); "
                f"repaired: {copy.messages} messages, {copy.seconds:.1f} s"
            )
        if copy.messages:
            os.replace(temporary, path)
            csv_path = path.with_suffix(".csv")
            if not csv_path.exists() and copy.rows:
                os.replace(csv_temporary, csv_path)
        return note
    finally:
        temporary.unlink(missing_ok=True)
        csv_temporary.unlink(missing_ok=True)


def _move_aside(path: Path, reason: str, kept_messages: int) -> str:
    """Move `path` into damaged/ under a name no earlier one has; the line that says so."""
    folder = path.parent / DAMAGED
    folder.mkdir(exist_ok=True)
    target = folder / path.name
    n = 1
    while target.exists():
        n += 1
        target = folder / f"{path.stem}-{n}{path.suffix}"
    os.rename(path, target)
    kept = (
        f"; the {kept_messages} messages before the damage are kept as the recording" if kept_messages else ""
    )
    return (
        f"Recording {path.stem} could not be repaired ({reason}): moved to "
        f"{DAMAGED}/{target.name} as it was{kept}"
    )


class _Copy:
    """The records read so far, written into a new MCAP and the /motors rows into a CSV."""

    def __init__(self, out: IO[bytes], csv_out: IO[str]) -> None:
        self.writer = Writer(out, compression=CompressionType.ZSTD)
        self.writer.start(profile="", library="pulse-pendant (repaired)")
        self.csv = csv.writer(csv_out, lineterminator="\n")
        self.schema_ids: dict[int, int] = {}
        self.channel_ids: dict[int, int] = {}
        self.motors_channel: int | None = None
        self.messages = 0
        self.rows = 0
        self.first_ns: int | None = None
        self.last_ns = 0
        self.motors_start_ns = 0

    @property
    def seconds(self) -> float:
        return (self.last_ns - self.first_ns) / 1e9 if self.first_ns is not None else 0.0

    def add(self, record: object) -> None:
        if isinstance(record, Schema) and record.id not in self.schema_ids:
            self.schema_ids[record.id] = self.writer.register_schema(
                record.name, record.encoding, record.data
            )
        elif isinstance(record, Channel) and record.id not in self.channel_ids:
            self.channel_ids[record.id] = self.writer.register_channel(
                record.topic,
                record.message_encoding,
                self.schema_ids.get(record.schema_id, 0),
                record.metadata,
            )
            if record.topic == "/motors":
                self.motors_channel = record.id
        elif isinstance(record, Message) and record.channel_id in self.channel_ids:
            self.writer.add_message(
                self.channel_ids[record.channel_id],
                record.log_time,
                record.data,
                record.publish_time,
                record.sequence,
            )
            self.messages += 1
            self.first_ns = record.log_time if self.first_ns is None else min(self.first_ns, record.log_time)
            self.last_ns = max(self.last_ns, record.log_time)
            if record.channel_id == self.motors_channel:
                self._add_row(record)
        elif isinstance(record, Attachment):
            self.writer.add_attachment(
                record.create_time, record.log_time, record.name, record.media_type, record.data
            )
        elif isinstance(record, Metadata):
            self.writer.add_metadata(record.name, record.metadata)

    def _add_row(self, record: Message) -> None:
        try:
            motors = json.loads(record.data)["motors"][:N_MOTORS]
            values = [float(motor[field]) for motor in motors for field in CSV_FIELDS]
        except (ValueError, KeyError, TypeError, IndexError, RecursionError):
            return  # a message that is not the pendant's: the MCAP keeps it, the CSV has no row for it
        if self.rows == 0:
            self.csv.writerow(csv_header())
            self.motors_start_ns = record.log_time
        self.csv.writerow([f"{(record.log_time - self.motors_start_ns) / 1e9:.6f}", *map(repr, values)])
        self.rows += 1

    def finish(self) -> None:
        self.writer.finish()
