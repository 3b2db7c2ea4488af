"""A client of the Foxglove WebSocket protocol, as Foxglove's app connects: the subprotocol, the server's
`serverInfo` and `advertise`, `subscribe`, and binary message data decoded with the advertised schemas (JSON
ones parsed; protobuf ones from the advertised descriptor set, by mcap's decoder).

The protocol's subprotocol is `foxglove.websocket.v1`, renamed `foxglove.sdk.v1` by Foxglove's SDK (the same
messages): the SDK's server accepts the new name only, so a client offers both, as Foxglove's app does."""

from __future__ import annotations

import base64
import json
import struct
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from mcap.records import Schema
from mcap_protobuf.decoder import DecoderFactory
from websockets.sync.client import ClientConnection, connect
from websockets.typing import Subprotocol

from tests.support.waiting import SAFETY_NET_S

SUBPROTOCOLS = ("foxglove.sdk.v1", "foxglove.websocket.v1")
MESSAGE_DATA = 0x01  # binary opcode: subscription id (u32), log time ns (u64), payload; little-endian
_HEADER = struct.Struct("<BIQ")
MAX_BYTES = 64 * 1024 * 1024


@dataclass(frozen=True)
class Advertised:
    id: int
    topic: str
    encoding: str
    schema_name: str
    schema: str
    schema_encoding: str


@dataclass(frozen=True)
class Received:
    topic: str
    log_time_ns: int
    payload: bytes


class FoxgloveClient:
    def __init__(self, url: str, timeout_s: float = SAFETY_NET_S) -> None:
        # No proxy (loopback), and room for /arm: the links' meshes come in one message.
        self.ws: ClientConnection = connect(
            url,
            subprotocols=[Subprotocol(name) for name in SUBPROTOCOLS],
            open_timeout=timeout_s,
            proxy=None,
            max_size=MAX_BYTES,
        )
        self.timeout_s = timeout_s
        self.server_info: dict[str, Any] = {}
        self.channels: dict[str, Advertised] = {}
        self._by_subscription: dict[int, str] = {}

    def close(self) -> None:
        self.ws.close()

    def __enter__(self) -> FoxgloveClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def wait_for_channels(self, *topics: str) -> None:
        """Read the server's text messages until every topic of `topics` is advertised."""
        deadline = time.monotonic() + self.timeout_s
        while not set(topics) <= set(self.channels):
            assert time.monotonic() < deadline, f"not advertised: {set(topics) - set(self.channels)}"
            self._handle(self.ws.recv(timeout=max(0.0, deadline - time.monotonic())))

    def subscribe(self, *topics: str) -> None:
        subscriptions = []
        for topic in topics:
            sub_id = len(self._by_subscription) + 1
            self._by_subscription[sub_id] = topic
            subscriptions.append({"id": sub_id, "channelId": self.channels[topic].id})
        self.ws.send(json.dumps({"op": "subscribe", "subscriptions": subscriptions}))

    def messages(self, seconds: float) -> Iterator[Received]:
        """The message data received within `seconds` (text messages are handled on the way)."""
        deadline = time.monotonic() + seconds
        while (left := deadline - time.monotonic()) > 0:
            try:
                frame = self.ws.recv(timeout=left)
            except TimeoutError:
                return
            received = self._handle(frame)
            if received is not None:
                yield received

    def _handle(self, frame: str | bytes) -> Received | None:
        if isinstance(frame, str):
            message = json.loads(frame)
            if message["op"] == "serverInfo":
                self.server_info = message
            elif message["op"] == "advertise":
                for channel in message["channels"]:
                    self.channels[channel["topic"]] = Advertised(
                        channel["id"],
                        channel["topic"],
                        channel["encoding"],
                        channel["schemaName"],
                        channel["schema"],
                        channel.get("schemaEncoding", ""),
                    )
            return None
        opcode, sub_id, log_time = _HEADER.unpack_from(frame)
        if opcode != MESSAGE_DATA:
            return None
        return Received(self._by_subscription[sub_id], log_time, frame[_HEADER.size :])

    def json_schema(self, topic: str) -> dict[str, Any]:
        channel = self.channels[topic]
        assert (channel.encoding, channel.schema_encoding) == ("json", "jsonschema"), channel
        schema: dict[str, Any] = json.loads(channel.schema)
        return schema

    def decode_protobuf(self, received: Received) -> Any:
        """A protobuf message decoded from its channel's advertised schema (a base64 FileDescriptorSet)."""
        channel = self.channels[received.topic]
        assert (channel.encoding, channel.schema_encoding) == ("protobuf", "protobuf"), channel
        schema = Schema(
            id=channel.id,
            name=channel.schema_name,
            encoding="protobuf",
            data=base64.b64decode(channel.schema),
        )
        decoder = DecoderFactory().decoder_for("protobuf", schema)
        assert decoder is not None
        return decoder(received.payload)
