"""Every JSON message of a real recording validates against the schema its own channel carries (read with
mcap's reader, checked with `jsonschema`), and those schemas refuse what a broken writer would write: an
empty message, a missing field, an unknown key, a wrong type."""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from mcap.reader import make_reader

from tests.support.recordings import make_recording

JSON_TOPICS = {"/joints", "/tcp", "/motors", "/io", "/program"}


def json_messages(mcap: Path) -> tuple[dict[str, dict[str, Any]], list[tuple[str, dict[str, Any]]]]:
    """The JSON channels' schemas by topic, and every JSON message with its topic, as stored in the file."""
    schemas: dict[str, dict[str, Any]] = {}
    messages: list[tuple[str, dict[str, Any]]] = []
    with mcap.open("rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            if channel.message_encoding != "json":
                continue
            assert schema is not None and schema.encoding == "jsonschema", channel.topic
            schemas[channel.topic] = json.loads(schema.data)
            messages.append((channel.topic, json.loads(message.data)))
    return schemas, messages


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, Any], list[tuple[str, Any]]]:
    return json_messages(make_recording(tmp_path_factory.mktemp("recordings"), seconds=2.0))


def test_every_message_of_a_real_recording_matches_its_channels_schema(
    recording: tuple[dict[str, Any], list[tuple[str, Any]]],
) -> None:
    schemas, messages = recording
    assert set(schemas) == JSON_TOPICS
    counts = Counter(topic for topic, _ in messages)
    assert set(counts) == JSON_TOPICS and counts["/joints"] >= 20, counts
    for topic, message in messages:
        jsonschema.Draft202012Validator.check_schema(schemas[topic])
        jsonschema.validate(message, schemas[topic], cls=jsonschema.Draft202012Validator)


def broken(message: dict[str, Any]) -> list[tuple[str, Any]]:
    """What a broken writer could write instead of `message`."""
    first = next(iter(message))
    missing = {key: value for key, value in message.items() if key != first}
    wrong_type = {**message, first: {"not": "this"}}
    return [
        ("empty", {}),
        ("missing " + first, missing),
        ("unknown key", {**message, "extra": 1}),
        ("wrong type", wrong_type),
    ]


def test_the_schemas_refuse_hand_broken_messages(
    recording: tuple[dict[str, Any], list[tuple[str, Any]]],
) -> None:
    schemas, messages = recording
    for topic in JSON_TOPICS:
        message = next(m for t, m in messages if t == topic)
        for what, bad in broken(message):
            with pytest.raises(jsonschema.ValidationError):
                jsonschema.validate(bad, schemas[topic], cls=jsonschema.Draft202012Validator)
                pytest.fail(f"{topic}: a message with {what} passes: {bad}")
    motors = next(m for t, m in messages if t == "/motors")
    del motors["motors"][0]["statorTemperature"]  # one motor's field lost deep in the message
    with pytest.raises(jsonschema.ValidationError, match="statorTemperature"):
        jsonschema.validate(motors, schemas["/motors"], cls=jsonschema.Draft202012Validator)
