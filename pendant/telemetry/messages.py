"""The recordings' JSON messages (/joints, /tcp, /motors, /io, /program) as pydantic models: the writer builds
each message from its model, and the channel's JSON schema is the model's own, so the schema a reader
validates against names every field as required and admits no other (extra="forbid")."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict

from pendant.controller.types import MotorStatus


class _Message(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Joints(_Message):
    model_config = ConfigDict(title="Joint angles")

    name: list[str]
    position_deg: list[float]
    velocity_rpm: list[float]


class Tcp(_Message):
    model_config = ConfigDict(title="TCP in the zero-point frame (m, rad; R = Rz(yaw) Ry(pitch) Rx(roll))")

    x: float
    y: float
    z: float
    roll: float
    pitch: float
    yaw: float


class MotorReading(MotorStatus):
    """One motor of GET /status/motors, the controller's field names; nothing else."""

    model_config = ConfigDict(extra="forbid", title="Motor")


class Motors(_Message):
    model_config = ConfigDict(title="GET /status/motors, the controller's field names")

    motors: list[MotorReading]


class Io(_Message):
    model_config = ConfigDict(title="Digital outputs and inputs (1 HIGH, 0 LOW) and the motion status")

    outputs: list[float]
    inputs: list[float]
    motion_status: str


class ProgramStep(_Message):
    model_config = ConfigDict(
        title="The program step running: its line as the page numbers it (1-based) and its text"
    )

    line: int
    step: str
    state: str


# topic -> (schema name, model of its messages)
MESSAGES: dict[str, tuple[str, type[_Message] | type[MotorReading]]] = {
    "/joints": ("pendant.Joints", Joints),
    "/tcp": ("pendant.Tcp", Tcp),
    "/motors": ("pendant.Motors", Motors),
    "/io": ("pendant.Io", Io),
    "/program": ("pendant.ProgramStep", ProgramStep),
}


def _inline(node: Any, definitions: dict[str, Any]) -> Any:
    """`$ref`s replaced by their definitions: one self-contained schema (no model here refers to itself)."""
    if isinstance(node, dict):
        if "$ref" in node:
            return _inline(definitions[node["$ref"].rsplit("/", 1)[-1]], definitions)
        return {key: _inline(value, definitions) for key, value in node.items() if key != "$defs"}
    if isinstance(node, list):
        return [_inline(item, definitions) for item in node]
    return node


def json_schema(model: type[BaseModel]) -> dict[str, Any]:
    """The model's JSON schema, self-contained (Foxglove reads a channel's schema without `$defs`)."""
    schema = model.model_json_schema()
    inlined: dict[str, Any] = _inline(schema, schema.get("$defs", {}))
    return inlined


CHANNELS: dict[str, tuple[str, dict[str, Any]]] = {
    topic: (name, json_schema(model)) for topic, (name, model) in MESSAGES.items()
}
