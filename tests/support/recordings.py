"""Real recordings made with the pendant's own recorder on the simulator (fake clock): a finished one, and
the bytes a killed pendant leaves (the file copied while its writer is still open); and damaged files."""

from __future__ import annotations

import io
import shutil
import struct
from pathlib import Path

import zstandard

from pendant.controller import MotionParams, Pose
from pendant.eventlog import EventKind, EventLog
from pendant.kinematics import ArmModel
from pendant.sim import FakeClock, SimController
from pendant.telemetry import ArmState, Telemetry, arm_drawing
from pendant.telemetry.mcap_scan import MAGIC

SAMPLE_PERIOD_S = 0.1
WALL_START = 1_800_000_000.0
# An MCAP header record (opcode 0x01): empty profile and library strings.
HEADER = bytes([0x01]) + struct.pack("<Q", 8) + struct.pack("<I", 0) + struct.pack("<I", 0)


def recording_arm(sim: SimController, clock: FakeClock, folder: Path) -> tuple[Telemetry, EventLog]:
    """The pendant's recorder on `sim` (times from `clock`), recording into `folder`, its event log wired to
    it, and the arm sent on a move: sample it with `telemetry.sample` as the clock advances."""
    events = EventLog(now=lambda: WALL_START + clock.now())
    telemetry = Telemetry(
        sim,
        now=clock.now,
        recordings_folder=folder,
        wall_now=lambda: WALL_START + clock.now(),
        arm=arm_drawing(ArmModel.load("pulse75")),
    )
    events.on_record(telemetry.log_event)
    telemetry.start_recording()
    sim.set_pose(Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0]), MotionParams(speed=30.0))
    return telemetry, events


def make_recording(folder: Path, seconds: float, unfinished_copy: Path | None = None) -> Path:
    """Record `seconds` of a moving arm (the arm drawn, an event, a program step) into `folder`; the
    finished .mcap. With `unfinished_copy`, the file's bytes just before it was finished are copied there
    (what kill -9 leaves)."""
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    telemetry, events = recording_arm(sim, clock, folder)
    for i in range(round(seconds / SAMPLE_PERIOD_S)):
        clock.advance(SAMPLE_PERIOD_S)
        if i == 5:
            events.record(EventKind.COMMAND, "operator", "PUT /freeze -> 200")
        telemetry.sample(ArmState(sim.get_position(), program=(1, "Move J to P1 @ 20%", "running")))
    [recording] = telemetry.recordings()
    mcap = next(f for f in recording.files if f.suffix == ".mcap")
    if unfinished_copy is not None:
        shutil.copy(mcap, unfinished_copy)
    telemetry.stop_recording()
    return mcap


def record(opcode: int, body: bytes) -> bytes:
    return bytes([opcode]) + struct.pack("<Q", len(body)) + body


def chunk(records: bytes, compression: str, compressed: bytes, declared_size: int | None = None) -> bytes:
    """A chunk record (opcode 0x06) holding `compressed`, saying it decompresses to `declared_size`."""
    size = len(records) if declared_size is None else declared_size
    body = (
        struct.pack("<QQQI", 0, 0, size, 0)
        + struct.pack("<I", len(compression))
        + compression.encode()
        + struct.pack("<Q", len(compressed))
        + compressed
    )
    return record(0x06, body)


def zstd_bomb(size: int) -> bytes:
    """A small file whose one chunk decompresses to `size` zero bytes (and says so)."""
    compressor = zstandard.ZstdCompressor().compressobj(size=size)
    block = bytes(1 << 20)
    compressed = b"".join(
        compressor.compress(block[: min(len(block), size - i)]) for i in range(0, size, len(block))
    )
    return MAGIC + HEADER + chunk(b"", "zstd", compressed + compressor.flush(), declared_size=size)


CRAFTED = (
    "magic-only",
    "random",
    "zeros",
    "header-then-zeros",
    "chunk-length-2^62",
    "chunk-declares-2^62",
    "lz4-garbage",
    "zstd-bomb",
    "zstd-bomb-declared-small",
)
_HUGE = struct.pack("<Q", 2**62)


def crafted(name: str) -> bytes:
    """A file no writer makes, named by what is wrong with it (one of CRAFTED)."""
    if name == "magic-only":
        return MAGIC + b"\x00\x00"
    if name == "random":
        return _random_bytes(1 << 20)
    if name == "zeros":
        return bytes(1 << 20)
    if name == "header-then-zeros":
        return MAGIC + HEADER + bytes(1 << 20)
    if name == "chunk-length-2^62":
        return MAGIC + HEADER + bytes([0x06]) + _HUGE + bytes(64)
    if name == "chunk-declares-2^62":
        return MAGIC + HEADER + chunk(b"", "zstd", b"\x28\xb5\x2f\xfd", declared_size=2**62)
    if name == "lz4-garbage":
        return MAGIC + HEADER + chunk(bytes(64), "lz4", _random_bytes(4096))
    if name == "zstd-bomb":
        return zstd_bomb(1 << 28)
    if name == "zstd-bomb-declared-small":
        bomb = zstd_bomb(1 << 28)
        return (
            MAGIC
            + HEADER
            + chunk(b"", "zstd", bomb[bomb.index(b"\x28\xb5\x2f\xfd") :], declared_size=1 << 20)
        )
    raise ValueError(name)


def bad_summary_offsets(finished: bytes) -> bytes:
    """A finished recording whose footer points its summary at byte 2^62."""
    return finished[: -len(MAGIC) - 20] + _HUGE + _HUGE + struct.pack("<I", 0) + MAGIC


def damaged_inside(finished: bytes, how: str) -> bytes:
    """A finished recording (it still ends with its summary and magic) whose first chunk is damaged: `how` is
    "chunk-length-2^62" (its record length), "chunk-declares-2^62" (its uncompressed size) or "chunk-garbage"
    (its compressed bytes replaced by random ones)."""
    at = len(MAGIC)
    while finished[at] != 0x06:  # the records before the first chunk: the header, the attachment, metadata
        at += 9 + int.from_bytes(finished[at + 1 : at + 9], "little")
    length = int.from_bytes(finished[at + 1 : at + 9], "little")
    data = bytearray(finished)
    if how == "chunk-length-2^62":
        data[at + 1 : at + 9] = _HUGE
    elif how == "chunk-declares-2^62":
        data[at + 9 + 16 : at + 9 + 24] = _HUGE
    elif how == "chunk-garbage":
        data[at + 9 + 64 : at + 9 + length] = _random_bytes(length - 64)
    else:
        raise ValueError(how)
    return bytes(data)


def _random_bytes(n: int) -> bytes:
    # Deterministic: a failure names the same bytes on every run.
    out = io.BytesIO()
    state = 0x9E3779B97F4A7C15
    while out.tell() < n:
        state = (state * 6364136223846793005 + 1442695040888963407) % 2**64
        out.write(state.to_bytes(8, "little"))
    return out.getvalue()[:n]
