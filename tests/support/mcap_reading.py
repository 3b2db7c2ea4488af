"""Recordings read back with the official `mcap` reader and its protobuf decoder (what Foxglove and Lichtblick
open)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from mcap.decoder import DecoderFactory as McapDecoderFactory
from mcap.reader import make_reader
from mcap.records import Schema
from mcap_protobuf.decoder import DecoderFactory

FOXGLOVE_SCHEMAS = {
    "/tf": "foxglove.FrameTransforms",
    "/arm": "foxglove.SceneUpdate",
    "/cell": "foxglove.SceneUpdate",
    "/tcp_path": "foxglove.SceneUpdate",
    "/events": "foxglove.Log",
}


class JsonDecoder(McapDecoderFactory):
    def decoder_for(self, message_encoding: str, schema: Schema | None) -> Any:
        return json.loads if message_encoding == "json" else None


def read_mcap(path: Path) -> tuple[dict[str, Any], list[tuple[str, int, Any]]]:
    """Schemas by topic (JSON schemas parsed; protobuf ones by name), and (topic, log time ns, message) in
    file order: JSON messages as dicts, Foxglove's protobuf messages decoded from the file's own schemas (Any:
    each topic has its own kind)."""
    decoder = DecoderFactory()
    with path.open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[decoder, JsonDecoder()])
        summary = reader.get_summary()
        assert summary is not None
        schemas: dict[str, Any] = {}
        for channel in summary.channels.values():
            schema = summary.schemas[channel.schema_id]
            if channel.topic in FOXGLOVE_SCHEMAS:
                assert (schema.encoding, channel.message_encoding) == ("protobuf", "protobuf")
                assert schema.name == FOXGLOVE_SCHEMAS[channel.topic]
                schemas[channel.topic] = schema.name
            else:
                assert (schema.encoding, channel.message_encoding) == ("jsonschema", "json")
                schemas[channel.topic] = json.loads(schema.data)
        messages: list[tuple[str, int, Any]] = []
        for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=False):
            messages.append((channel.topic, message.log_time, decoded))
    return schemas, messages
