"""Finishing a recording whose pendant died (kill -9, power cut): every record up to the last flushed chunk is
copied into a new, properly finished MCAP (the official `mcap` reader and writer), and the CSV beside it is
made from its /motors channel. Run on start for the recordings folder."""

from __future__ import annotations

import csv
import io
import json
import os
from pathlib import Path

from mcap.exceptions import McapError
from mcap.records import Attachment, Channel, Message, Metadata, Schema
from mcap.stream_reader import StreamReader
from mcap.writer import CompressionType, Writer

from pendant.telemetry.recorder import CSV_FIELDS, N_MOTORS, csv_header
from pendant.telemetry.recordings import PREFIX

MAGIC = b"\x89MCAP0\r\n"


def finished(path: Path) -> bool:
    """An MCAP file ends with its magic bytes once its writer closed it."""
    size = path.stat().st_size
    if size < 2 * len(MAGIC):
        return False
    with path.open("rb") as stream:
        stream.seek(size - len(MAGIC))
        return stream.read() == MAGIC


def repair_all(folder: Path) -> list[str]:
    """Finish every unfinished recording in `folder`; one line per file for the event log."""
    notes = []
    for path in sorted(folder.glob(f"{PREFIX}*.mcap")):
        try:
            if not finished(path):
                notes.append(repair(path))
        except OSError as error:  # a read-only folder: the file stays as it is, readable up to its last flush
            notes.append(f"Recording {path.stem} was not finished and could not be repaired ({error})")
    return notes


def repair(path: Path) -> str:
    """Rewrite `path` with what it holds up to its last complete record; write its CSV when missing."""
    messages = 0
    first_ns: int | None = None
    last_ns = 0
    motors_rows: list[list[float]] = []
    motors_channel: int | None = None
    out = io.BytesIO()
    writer = Writer(out, compression=CompressionType.ZSTD)
    writer.start(profile="", library="pulse-pendant (repaired)")
    schema_ids: dict[int, int] = {}
    channel_ids: dict[int, int] = {}
    with path.open("rb") as stream:
        try:
            for record in StreamReader(stream, skip_magic=False).records:
                if isinstance(record, Schema):
                    schema_ids[record.id] = writer.register_schema(record.name, record.encoding, record.data)
                elif isinstance(record, Channel):
                    channel_ids[record.id] = writer.register_channel(
                        record.topic,
                        record.message_encoding,
                        schema_ids.get(record.schema_id, 0),
                        record.metadata,
                    )
                    if record.topic == "/motors":
                        motors_channel = record.id
                elif isinstance(record, Message) and record.channel_id in channel_ids:
                    writer.add_message(
                        channel_ids[record.channel_id],
                        record.log_time,
                        record.data,
                        record.publish_time,
                        record.sequence,
                    )
                    messages += 1
                    first_ns = record.log_time if first_ns is None else min(first_ns, record.log_time)
                    last_ns = max(last_ns, record.log_time)
                    if record.channel_id == motors_channel:
                        motors_rows.append(_csv_row(record))
                elif isinstance(record, Attachment):
                    writer.add_attachment(
                        record.create_time, record.log_time, record.name, record.media_type, record.data
                    )
                elif isinstance(record, Metadata):
                    writer.add_metadata(record.name, record.metadata)
        except (McapError, EOFError, ValueError):
            pass  # the unfinished chunk at the end: everything before it is kept
    writer.finish()
    temporary = path.with_suffix(".mcap.tmp")
    temporary.write_bytes(out.getvalue())
    os.replace(temporary, path)
    csv_path = path.with_suffix(".csv")
    if not csv_path.exists() and motors_rows:
        csv_path.write_text(_csv_text(motors_rows, int(motors_rows[0][0])))
    seconds = (last_ns - first_ns) / 1e9 if first_ns is not None else 0.0
    return (
        f"Recording {path.stem} was not finished (the pendant stopped); "
        f"repaired: {messages} messages, {seconds:.1f} s"
    )


def _csv_row(record: Message) -> list[float]:
    motors = json.loads(record.data)["motors"][:N_MOTORS]
    row = [float(record.log_time)]
    for motor in motors:
        row.extend(float(motor[field]) for field in CSV_FIELDS)
    return row


def _csv_text(rows: list[list[float]], start_ns: int) -> str:
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(csv_header())
    for row in rows:
        writer.writerow([f"{(row[0] - start_ns) / 1e9:.6f}", *(repr(v) for v in row[1:])])
    return out.getvalue()
