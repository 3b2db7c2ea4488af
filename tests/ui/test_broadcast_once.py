"""The shared scene's updates are serialised once whatever the number of browsers (issue 37): viser 1.1.1 did
it once per browser, which with 60 viewers took most of its event loop. A real viser server on loopback with
the pendant's producer installed, browsers as bare websockets reading every frame."""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from typing import Any

import pytest
import viser
import websockets
import zstandard
from viser import _messages

from pendant.ui.kit.viser_broadcast import serialise_broadcasts_once
from tests.support.headless_viewer import next_messages, open_viewer
from tests.support.ports import LOOPBACK, free_port
from tests.support.waiting import wait_until

BROWSERS = 6
UPDATES = 20
READ_TIMEOUT_S = 30.0  # generous: the machine may be loaded


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    assert serialise_broadcasts_once()
    server = viser.ViserServer(host=LOOPBACK, port=free_port(), verbose=False)
    try:
        yield server
    finally:
        server.stop()


async def last_position(ws: websockets.ClientConnection, x: float) -> None:
    """Read until /probe's position with this x has come."""
    zstd = zstandard.ZstdDecompressor()
    async with asyncio.timeout(READ_TIMEOUT_S):
        while True:
            for message in await next_messages(ws, zstd):
                probe = message.get("type") == "SetPositionMessage" and message.get("name") == "/probe"
                if probe and abs(message["position"][0] - x) < 1e-9:
                    return


async def watch_updates(server: viser.ViserServer) -> None:
    browsers = [await open_viewer(server.get_port()) for _ in range(BROWSERS)]
    try:
        await asyncio.to_thread(lambda: _wait_connected(server))
        probe = server.scene.add_frame("/probe")
        for i in range(UPDATES):
            probe.position = (0.01 * (i + 1), 0.0, 0.0)
            await asyncio.sleep(0.05)  # each in a window of its own: nothing merged away
        await asyncio.gather(*(last_position(ws, 0.01 * UPDATES) for ws in browsers))
    finally:
        for ws in browsers:
            await ws.close()


def _wait_connected(server: viser.ViserServer) -> None:
    wait_until(lambda: len(server.get_clients()) == BROWSERS, READ_TIMEOUT_S, "the browsers connected")


def test_each_scene_update_is_serialised_once_for_six_browsers(
    server: viser.ViserServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    serialised: list[Any] = []
    original = _messages.Message.as_serializable_dict

    def counting(message: _messages.Message, binaries: Any = None) -> dict[str, Any]:
        if isinstance(message, _messages.SetPositionMessage) and message.name == "/probe":
            serialised.append(message.position)
        return original(message, binaries)

    monkeypatch.setattr(_messages.SetPositionMessage, "as_serializable_dict", counting)
    asyncio.run(watch_updates(server))
    assert 0 < len(serialised) <= UPDATES, f"{len(serialised)} serialisations of {UPDATES} updates"
