"""An MCAP file read record by record without trusting it: what repair and replay read through.

The official reader believes a record's declared length, a chunk's declared size and the summary's offsets,
so a damaged or crafted file can make it allocate gigabytes, decompress a bomb or run for minutes. Here every
declared length is checked against what the file still holds, a record is at most MAX_RECORD_BYTES, a chunk
decompresses to at most MAX_CHUNK_BYTES (and to no more than it declares), all chunks of a file to at most
DECOMPRESS_RATIO times its size, and the whole read to at most `time_limit_s`: past any of these the file is
refused with where and why (Damaged). A file that simply ends inside a record, as a killed writer leaves it,
is Truncated. The data section is read in file order; the summary (indexes, offsets) is never used."""

from __future__ import annotations

import io
import time
from collections.abc import Callable, Iterator
from typing import BinaryIO

import lz4.frame
import zstandard
from mcap.data_stream import ReadDataStream
from mcap.opcode import Opcode
from mcap.records import (
    Attachment,
    Channel,
    Chunk,
    DataEnd,
    Footer,
    Header,
    McapRecord,
    Message,
    Metadata,
    Schema,
)

MAGIC = b"\x89MCAP0\r\n"
MAX_RECORD_BYTES = (
    64 * 1024 * 1024
)  # the pendant's chunks are about 1 MB, its one attachment (the URDF) smaller
MAX_CHUNK_BYTES = 64 * 1024 * 1024  # decompressed
DECOMPRESS_RATIO = 100  # all chunks together: JSON telemetry compresses about 10 to 1
DECOMPRESS_FLOOR = 64 * 1024 * 1024  # ... and a small file may still hold a full chunk
_HEAD = 9  # a record's opcode (1 byte) and length (8 bytes)
# Records read from the data section; others (indexes, statistics) are skipped by their length.
_READERS: dict[int, Callable[[ReadDataStream], McapRecord]] = {
    Opcode.HEADER: Header.read,
    Opcode.SCHEMA: Schema.read,
    Opcode.CHANNEL: Channel.read,
    Opcode.ATTACHMENT: Attachment.read,
    Opcode.METADATA: Metadata.read,
    Opcode.DATA_END: DataEnd.read,
    Opcode.FOOTER: Footer.read,
}


class Damaged(Exception):
    """The file is not a readable recording from some point on; `str()` says where and why."""


class Truncated(Damaged):
    """The file ends inside a record: what a writer that was killed leaves behind."""


def records(stream: BinaryIO, size: int, time_limit_s: float) -> Iterator[McapRecord]:
    """The records of the MCAP in `stream` (`size` bytes) up to its data section's end, chunks opened into
    the records they hold; Damaged or Truncated where it stops being readable."""
    reader = _Reader(stream, size, time_limit_s)
    magic = stream.read(len(MAGIC))
    if magic != MAGIC[: len(magic)]:
        raise Damaged("it does not start as an MCAP file")
    if len(magic) < len(MAGIC):
        raise Truncated("it ends inside its first bytes")
    reader.position = len(MAGIC)
    first = True
    while True:
        opcode, body = reader.next_record()
        if first and opcode != Opcode.HEADER:
            raise Damaged("its first record is not an MCAP header")
        first = False
        if opcode == Opcode.CHUNK:
            yield from reader.open_chunk(body)
            continue
        record = _parse(opcode, body, reader.position)
        if record is not None:
            yield record
        if isinstance(record, (DataEnd, Footer)):
            return


class _Reader:
    def __init__(self, stream: BinaryIO, size: int, time_limit_s: float) -> None:
        self.stream = stream
        self.size = size
        self.position = 0
        self.deadline = time.monotonic() + time_limit_s
        self.time_limit_s = time_limit_s
        self.decompress_left = max(DECOMPRESS_FLOOR, DECOMPRESS_RATIO * size)

    def next_record(self) -> tuple[int, bytes]:
        if time.monotonic() > self.deadline:
            raise Damaged(f"reading it took longer than {self.time_limit_s:g} s (at byte {self.position})")
        head = self.stream.read(_HEAD)
        if len(head) < _HEAD:
            raise Truncated(f"it ends inside a record at byte {self.position}")
        opcode, length = head[0], int.from_bytes(head[1:], "little")
        if opcode == 0:
            raise Damaged(f"byte {self.position} does not start an MCAP record")
        if length > MAX_RECORD_BYTES:  # past the end or not, no writer made it: the rest is not thrown away
            raise Damaged(
                f"the record at byte {self.position} is {length} bytes, more than a recording holds"
            )
        body = self.stream.read(length)
        if len(body) < length:
            raise Truncated(f"it ends inside a record at byte {self.position}")
        self.position += _HEAD + length
        return opcode, body

    def open_chunk(self, body: bytes) -> Iterator[McapRecord]:
        where = self.position - len(body) - _HEAD
        chunk = _parse(Opcode.CHUNK, body, where)
        assert isinstance(chunk, Chunk)
        if chunk.uncompressed_size > min(MAX_CHUNK_BYTES, self.decompress_left):
            raise Damaged(
                f"the chunk at byte {where} says it holds {chunk.uncompressed_size} bytes, too many"
            )
        data = _decompress(chunk, where)
        self.decompress_left -= len(data)
        inner = io.BytesIO(data)
        while inner.tell() < len(data):
            if time.monotonic() > self.deadline:
                raise Damaged(f"reading it took longer than {self.time_limit_s:g} s (at byte {where})")
            head = inner.read(_HEAD)
            length = int.from_bytes(head[1:], "little")
            if len(head) < _HEAD or head[0] == 0 or length > len(data) - inner.tell():
                raise Damaged(f"the chunk at byte {where} holds a damaged record")
            record = _parse(head[0], inner.read(length), where)
            if isinstance(record, (Schema, Channel, Message)):
                yield record


def _decompress(chunk: Chunk, where: int) -> bytes:
    """The chunk's records, at most its declared size: a bomb stops there."""
    limit = chunk.uncompressed_size
    try:
        if chunk.compression == "zstd":
            with zstandard.ZstdDecompressor().stream_reader(io.BytesIO(chunk.data)) as reader:
                data = reader.read(limit + 1)
        elif chunk.compression == "lz4":
            data = lz4.frame.LZ4FrameDecompressor().decompress(chunk.data, max_length=limit + 1)
        elif chunk.compression == "":
            data = chunk.data
        else:
            raise Damaged(f"the chunk at byte {where} is compressed with {chunk.compression[:20]!r}, unknown")
    except (zstandard.ZstdError, RuntimeError, ValueError) as error:
        raise Damaged(f"the chunk at byte {where} does not decompress ({error})") from error
    if len(data) != limit:
        raise Damaged(f"the chunk at byte {where} does not hold the {limit} bytes it says")
    return data


def _parse(opcode: int, body: bytes, where: int) -> McapRecord | None:
    """The record in `body` (None: a kind repair and replay do not need); Damaged when it does not parse."""
    stream = ReadDataStream(io.BytesIO(body))
    try:
        if opcode == Opcode.MESSAGE:
            return Message.read(stream, len(body))
        if opcode == Opcode.CHUNK:
            return Chunk.read(stream)
        read = _READERS.get(opcode)
        return None if read is None else read(stream)
    except Exception as error:  # struct.error, EndOfFile, UnicodeDecodeError, ...: whatever the bytes make
        raise Damaged(f"the record at byte {where} is damaged ({type(error).__name__})") from error
