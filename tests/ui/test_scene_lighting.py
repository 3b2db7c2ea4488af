"""How the 3D view is lit (pendant/ui/scene/arm.py): by default with lights alone, so a page in software WebGL
never decodes and prefilters an HDR map at load (benchmarks/page_load.py); with --environment-map, by the
map the operator names. Read the way a browser gets it: a real viser server on loopback, the scene's first
messages over its websocket."""

from __future__ import annotations

import asyncio
import inspect
import typing
from collections.abc import Iterator
from typing import Any

import pytest
import viser
import zstandard

from pendant.config import ENVIRONMENT_MAPS
from pendant.paths import urdf_path
from pendant.ui.scene.arm import ArmScene
from tests.support.headless_viewer import next_messages, open_viewer
from tests.support.ports import LOOPBACK, free_port

READ_TIMEOUT_S = 30.0  # generous: the machine may be loaded


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    server = viser.ViserServer(host=LOOPBACK, port=free_port(), verbose=False)
    try:
        yield server
    finally:
        server.stop()


async def first_messages(port: int) -> list[dict[str, Any]]:
    """What a newcomer's page is sent until the arm's base mesh has come (the scene is built by then)."""
    ws = await open_viewer(port)
    zstd = zstandard.ZstdDecompressor()
    seen: list[dict[str, Any]] = []
    try:
        async with asyncio.timeout(READ_TIMEOUT_S):
            while not any(str(m.get("name", "")).startswith("/arm") for m in seen):
                seen += await next_messages(ws, zstd)
    finally:
        await ws.close()
    return seen


def environment_maps(messages: list[dict[str, Any]]) -> list[Any]:
    return [m["hdri_data"] for m in messages if m.get("type") == "EnvironmentMapMessage"]


def test_by_default_the_view_is_lit_by_lights_with_no_environment_map(server: viser.ViserServer) -> None:
    ArmScene(server, urdf_path("pulse75"))
    messages = asyncio.run(first_messages(server.get_port()))
    assert environment_maps(messages) == [None], "a page would decode viser's HDR map at load"
    fills = [m for m in messages if m.get("type") == "HemisphereLightMessage"]
    assert len(fills) == 1, "the arm would be lit by two directional lights alone: dark from most sides"
    assert fills[0]["props"]["intensity"] > 0


def test_a_named_environment_map_is_sent_to_the_page(server: viser.ViserServer) -> None:
    ArmScene(server, urdf_path("pulse75"), environment_map="studio")
    messages = asyncio.run(first_messages(server.get_port()))
    (hdri,) = environment_maps(messages)
    assert isinstance(hdri, bytes) and len(hdri) > 10_000, "the studio map's image was not sent"
    assert not [m for m in messages if m.get("type") == "HemisphereLightMessage"], "lit twice"


def test_the_flag_offers_the_maps_viser_has() -> None:
    hint = typing.get_type_hints(viser.SceneApi.configure_environment_map)["hdri"]
    literal = next(arg for arg in typing.get_args(hint) if typing.get_origin(arg) is typing.Literal)
    assert set(ENVIRONMENT_MAPS) == set(typing.get_args(literal)), inspect.signature(
        viser.SceneApi.configure_environment_map
    )
