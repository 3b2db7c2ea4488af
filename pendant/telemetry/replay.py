"""A finished recording read back for replay: the joint angles (/joints), the event log (/events) and the
program step (/program) as arrays on one time axis, seconds since the first sample.

Read through mcap_scan (every declared length checked against the file, decompression capped, at most
REPLAY_TIME_LIMIT_S), the official `mcap` records and the protobuf decoder for Foxglove's foxglove.Log built
from the file's own schema, as Foxglove does. Bounded: a file over MAX_REPLAY_BYTES is refused before it is
opened, and no more than MAX_SAMPLES samples, MAX_EVENTS events and MAX_PROGRAM_STEPS step changes are kept.
Whatever the bytes, the answer is a Replay or a ReplayError that says why."""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np
from mcap.records import Channel, Message, Schema
from mcap_protobuf.decoder import DecoderFactory as ProtobufDecoderFactory

from pendant.telemetry.mcap_scan import Damaged, Truncated, records
from pendant.telemetry.recorder import MAX_ROWS

MAX_REPLAY_BYTES = 512 * 1024 * 1024  # a two-hour recording (the longest one made) is about 60 MB
MAX_SAMPLES = MAX_ROWS  # two hours at 10 Hz
MAX_EVENTS = 10_000
MAX_PROGRAM_STEPS = 50_000
REPLAY_TIME_LIMIT_S = 30.0  # a two-hour recording reads in a few seconds
N_JOINTS = 6
TOPICS = ("/joints", "/events", "/program")
STOP_WORDS = ("stop", "freeze", "emergency", "error", "fail", "refused", "collision")  # events worth a jump


class ReplayError(Exception):
    """The recording cannot be replayed; the message says which and why."""


@dataclass(frozen=True)
class ReplayEvent:
    t_s: float
    level: str  # foxglove.Log's level: INFO, WARNING, ERROR
    who: str
    message: str  # "[kind] what happened", as the event log said it

    @property
    def notable(self) -> bool:
        """A stop or an error (or a refusal): what the replay's "Jump to" lists."""
        text = self.message.lower()
        return self.level in ("ERROR", "WARNING") or any(word in text for word in STOP_WORDS)


@dataclass(frozen=True)
class ProgramStep:
    t_s: float
    line: int  # 1-based, as the Program tab numbers it; 0 when no step runs
    step: str
    state: str


@dataclass(frozen=True)
class Replay:
    """`times_s` (N,) ascending, `q_deg` (N, 6): the joints as recorded; `start_ns`: the first sample's wall
    time."""

    name: str
    start_ns: int
    times_s: np.ndarray
    q_deg: np.ndarray
    events: tuple[ReplayEvent, ...]
    steps: tuple[ProgramStep, ...]

    @property
    def duration_s(self) -> float:
        return float(self.times_s[-1]) if len(self.times_s) else 0.0

    def index_at(self, t_s: float) -> int:
        """The last sample at or before `t_s` (the first one before the recording starts)."""
        return max(0, int(np.searchsorted(self.times_s, t_s, side="right")) - 1)

    def q_at(self, t_s: float) -> np.ndarray:
        """The joint angles (radians) recorded at `t_s`."""
        return np.radians(self.q_deg[self.index_at(t_s)])

    @cached_property
    def _step_times(self) -> np.ndarray:
        return np.array([step.t_s for step in self.steps], dtype=float)

    @cached_property
    def _event_times(self) -> np.ndarray:
        return np.array([event.t_s for event in self.events], dtype=float)

    def step_at(self, t_s: float) -> ProgramStep | None:
        """The program step running at `t_s` (None: no program ran yet)."""
        i = int(np.searchsorted(self._step_times, t_s, side="right")) - 1
        return self.steps[i] if i >= 0 else None

    def events_until(self, t_s: float, count: int) -> list[ReplayEvent]:
        """The last `count` events at or before `t_s`, newest first."""
        end = int(np.searchsorted(self._event_times, t_s, side="right"))
        return list(reversed(self.events[max(0, end - count) : end]))


_LEVELS = {1: "DEBUG", 2: "INFO", 3: "WARNING", 4: "ERROR", 5: "FATAL"}
_Decode = Callable[[bytes], Any]


def load_replay(
    path: Path, max_bytes: int = MAX_REPLAY_BYTES, time_limit_s: float = REPLAY_TIME_LIMIT_S
) -> Replay:
    """Read `path` (a finished recording) into a Replay; ReplayError when it is too big, unreadable, damaged,
    slower than `time_limit_s` to read, or holds no joint samples."""
    try:
        size = path.stat().st_size
    except OSError as error:
        raise ReplayError(f"Cannot open {path.name}: {error.strerror or error}") from error
    if size > max_bytes:
        raise ReplayError(
            f"{path.name} is {size / 1e6:.0f} MB: replay reads at most {max_bytes / 1e6:.0f} MB "
            "(open it in Foxglove instead)"
        )
    times: list[int] = []
    angles: list[list[float]] = []
    events: list[tuple[int, ReplayEvent]] = []
    steps: list[tuple[int, ProgramStep]] = []
    schemas: dict[int, Schema] = {}
    channels: dict[int, tuple[str, _Decode]] = {}
    try:
        with path.open("rb") as stream:
            for record in records(stream, size, time_limit_s):
                if isinstance(record, Schema):
                    schemas[record.id] = record
                elif isinstance(record, Channel) and record.topic in TOPICS:
                    channels[record.id] = (record.topic, _decoder(record, schemas.get(record.schema_id)))
                elif isinstance(record, Message) and record.channel_id in channels:
                    topic, decode = channels[record.channel_id]
                    decoded = decode(record.data)
                    if topic == "/joints" and len(times) < MAX_SAMPLES:
                        q = [float(v) for v in decoded["position_deg"][:N_JOINTS]]
                        if len(q) == N_JOINTS:
                            times.append(record.log_time)
                            angles.append(q)
                    elif topic == "/events" and len(events) < MAX_EVENTS:
                        level = _LEVELS.get(decoded.level, "INFO")
                        events.append(
                            (record.log_time, ReplayEvent(0.0, level, decoded.name, decoded.message))
                        )
                    elif topic == "/program" and len(steps) < MAX_PROGRAM_STEPS:
                        step = ProgramStep(
                            0.0, int(decoded["line"]), str(decoded["step"]), str(decoded["state"])
                        )
                        steps.append((record.log_time, step))
    except Truncated as error:
        raise ReplayError(
            f"{path.name} is not finished ({error}): the pendant finishes such a file when it starts"
        ) from error
    except Damaged as error:
        raise ReplayError(f"{path.name} cannot be read as a recording: {error}") from error
    except Exception as error:  # a message that is not what its topic says: bytes from anywhere
        raise ReplayError(
            f"{path.name} cannot be read as a recording (a {type(error).__name__} in its messages)"
        ) from error
    if not times:
        raise ReplayError(f"{path.name} holds no joint samples")
    order = np.argsort(times, kind="stable")
    start_ns = times[int(order[0])]
    return Replay(
        name=path.stem,
        start_ns=start_ns,
        times_s=(np.asarray(times, dtype=np.int64)[order] - start_ns) / 1e9,
        q_deg=np.asarray(angles, dtype=float)[order],
        events=tuple(
            ReplayEvent((t - start_ns) / 1e9, e.level, e.who, e.message)
            for t, e in sorted(events, key=_first)
        ),
        steps=tuple(
            ProgramStep((t - start_ns) / 1e9, s.line, s.step, s.state) for t, s in sorted(steps, key=_first)
        ),
    )


def _decoder(channel: Channel, schema: Schema | None) -> _Decode:
    """JSON for the pendant's series, the file's own protobuf schema for foxglove.Log."""
    if channel.message_encoding == "json":
        return json.loads
    decode = ProtobufDecoderFactory().decoder_for(channel.message_encoding, schema)
    if decode is None:
        raise Damaged(
            f"its topic {channel.topic} is in {channel.message_encoding[:20]!r}, which replay cannot read"
        )
    return decode


def _first(pair: tuple[int, object]) -> int:
    return pair[0]
