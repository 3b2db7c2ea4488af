"""A recording as an MCAP file (the `mcap` package): JSON messages on JSON-schema channels, which Foxglove and
Lichtblick open as they are. Channels: /joints, /tcp, /motors, /io, /events; log times are wall-clock ns."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import IO, Any

from mcap.writer import CompressionType, Writer

from pendant import __version__
from pendant.controller.types import MotorStatus, Position
from pendant.telemetry.recorder import CSV_FIELDS

_NUMBER = {"type": "number"}
_NUMBERS = {"type": "array", "items": _NUMBER}
_STRINGS = {"type": "array", "items": {"type": "string"}}

# topic -> (schema name, JSON schema of its messages)
CHANNELS: dict[str, tuple[str, dict[str, Any]]] = {
    "/joints": (
        "pendant.Joints",
        {
            "type": "object",
            "title": "Joint angles",
            "properties": {"name": _STRINGS, "position_deg": _NUMBERS, "velocity_rpm": _NUMBERS},
        },
    ),
    "/tcp": (
        "pendant.Tcp",
        {
            "type": "object",
            "title": "TCP in the zero-point frame (m, rad; R = Rz(yaw) Ry(pitch) Rx(roll))",
            "properties": {k: _NUMBER for k in ("x", "y", "z", "roll", "pitch", "yaw")},
        },
    ),
    "/motors": (
        "pendant.Motors",
        {
            "type": "object",
            "title": "GET /status/motors, the controller's field names",
            "properties": {
                "motors": {
                    "type": "array",
                    "items": {"type": "object", "properties": {f: _NUMBER for f in CSV_FIELDS}},
                }
            },
        },
    ),
    "/io": (
        "pendant.Io",
        {
            "type": "object",
            "title": "Digital outputs and inputs (1 HIGH, 0 LOW) and the motion status",
            "properties": {"outputs": _NUMBERS, "inputs": _NUMBERS, "motion_status": {"type": "string"}},
        },
    ),
    "/events": (
        "pendant.Event",
        {
            "type": "object",
            "title": "An event of the pendant's log",
            "properties": {
                "id": {"type": "integer"},
                "kind": {"type": "string"},
                "source": {"type": "string"},
                "message": {"type": "string"},
            },
        },
    ),
}


class McapFile:
    """One recording being written. Not thread-safe: the caller (Telemetry) holds its lock."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._stream: IO[bytes] = path.open("wb")
        self._writer = Writer(self._stream, compression=CompressionType.ZSTD)
        self._writer.start(profile="", library=f"pulse-pendant {__version__}")
        self._channels: dict[str, int] = {}
        for topic, (name, schema) in CHANNELS.items():
            schema_id = self._writer.register_schema(
                name=name, encoding="jsonschema", data=json.dumps(schema).encode()
            )
            self._channels[topic] = self._writer.register_channel(
                topic=topic, message_encoding="json", schema_id=schema_id
            )
        self._sequence = 0
        self.messages = 0

    def write(self, topic: str, time_ns: int, message: Mapping[str, Any]) -> None:
        self._sequence += 1
        self._writer.add_message(
            channel_id=self._channels[topic],
            log_time=time_ns,
            publish_time=time_ns,
            sequence=self._sequence,
            data=json.dumps(message).encode(),
        )
        self.messages += 1

    def write_sample(
        self,
        time_ns: int,
        motors: Sequence[MotorStatus],
        tcp: Position | None,
        outputs: Sequence[float],
        inputs: Sequence[float],
        motion_status: str | None,
    ) -> None:
        self.write(
            "/joints",
            time_ns,
            {
                "name": [f"J{i + 1}" for i in range(len(motors))],
                "position_deg": [m.angle for m in motors],
                "velocity_rpm": [m.rotorVelocity for m in motors],
            },
        )
        self.write("/motors", time_ns, {"motors": [m.model_dump() for m in motors]})
        if tcp is not None:
            self.write("/tcp", time_ns, {**tcp.point.model_dump(), **tcp.rotation.model_dump()})
        self.write(
            "/io",
            time_ns,
            {"outputs": list(outputs), "inputs": list(inputs), "motion_status": motion_status or ""},
        )

    def close(self) -> None:
        self._writer.finish()
        self._stream.close()
