"""The page's stops never wait for viser's callback pool (issue 32): with every one of its 32 threads held
(as 40 slow clicks held them), a browser that connects still gets Freeze, and Freeze, Esc, Protective stop
and the program's Pause and Stop still act. The page in-process on loopback, the simulator on a fake clock
(its move stays RUNNING until something stops it), browsers as bare websockets (what a browser sends)."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Iterator

import msgspec
import pytest
import websockets
import zstandard

from pendant.controller import MotionParams, MotionStatus, Pose
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from tests.support.headless_viewer import click_message, next_messages, open_viewer
from tests.support.pages import pendant_page
from tests.support.waiting import wait_until

VISER_POOL = 32  # viser 1.1.1's callback pool (ViserServer._thread_executor)
PAGE_TIMEOUT_S = 30.0  # generous: the machine may be loaded; nothing here measures speed
STOP_TIMEOUT_S = 60.0  # a safety net: a stop that waited for the held pool would never come
AWAY = Pose(angles=[120.0, -60.0, 60.0, -90.0, -90.0, 0.0])


@pytest.fixture
def held_pool(sim: SimController) -> Iterator[PendantUI]:
    """A page whose viser callback pool is busy with 32 callbacks that do not end (until the test does)."""
    with pendant_page(sim, sim.arm) as page:
        release = threading.Event()
        for _ in range(VISER_POOL + 8):
            page.server._thread_executor.submit(release.wait)
        try:
            yield page
        finally:
            release.set()


async def controls(ws: websockets.ClientConnection, wanted: set[str]) -> dict[str, str]:
    """Read the page until buttons (and palette commands) with these labels have come: label -> uuid."""
    zstd = zstandard.ZstdDecompressor()
    found: dict[str, str] = {}
    async with asyncio.timeout(PAGE_TIMEOUT_S):
        while not wanted <= found.keys():
            for message in await next_messages(ws, zstd):
                kind, props = message.get("type"), message.get("props", {})
                if kind == "GuiButtonMessage":
                    found.setdefault(str(props.get("label")), str(message["uuid"]))
                elif kind == "RegisterCommandMessage":
                    found.setdefault(f"command {props.get('label')}", str(message["uuid"]))
    return found


def moving(sim: SimController) -> None:
    sim.freeze()
    sim.set_pose(AWAY, MotionParams(speed=10.0))
    assert sim.get_motion_status() is MotionStatus.RUNNING  # the fake clock holds it mid-move


def stops(sim: SimController, status: MotionStatus, what: str) -> None:
    wait_until(lambda: sim.get_motion_status() is status, STOP_TIMEOUT_S, what)


def trigger(uuid: str) -> bytes:
    """What the page sends when a palette command's hotkey is pressed (Esc for Freeze)."""
    return msgspec.msgpack.encode({"type": "CommandTriggerMessage", "uuid": uuid})


async def press_stops(page: PendantUI, sim: SimController) -> None:
    ws = await open_viewer(page.server.get_port())
    try:
        found = await controls(ws, {"Freeze", "command Freeze", "Protective stop"})
        moving(sim)
        await ws.send(click_message(found["Freeze"]))
        await asyncio.to_thread(stops, sim, MotionStatus.IDLE, "Freeze")
        moving(sim)
        await ws.send(trigger(found["command Freeze"]))
        await asyncio.to_thread(stops, sim, MotionStatus.IDLE, "Esc")
        moving(sim)
        await ws.send(click_message(found["Protective stop"]))
        await asyncio.to_thread(stops, sim, MotionStatus.ERROR, "Protective stop")
    finally:
        await ws.close()


def test_a_new_browser_gets_freeze_and_the_stops_work_with_the_pool_held(
    held_pool: PendantUI, sim: SimController
) -> None:
    asyncio.run(press_stops(held_pool, sim))


def test_the_programs_pause_and_stop_work_with_the_pool_held(held_pool: PendantUI) -> None:
    programs = held_pool.programs
    pressed: list[str] = []
    programs.pause = lambda: pressed.append("pause")  # type: ignore[method-assign]  # spies: no run is needed
    programs.stop = lambda cause="": pressed.append("stop")  # type: ignore[method-assign]

    async def press() -> None:
        ws = await open_viewer(held_pool.server.get_port())
        try:
            found = await controls(ws, {"Pause", "Stop"})
            await ws.send(click_message(found["Pause"]))
            await asyncio.to_thread(wait_until, lambda: pressed == ["pause"], STOP_TIMEOUT_S, "Pause")
            await ws.send(click_message(found["Stop"]))
            await asyncio.to_thread(wait_until, lambda: pressed == ["pause", "stop"], STOP_TIMEOUT_S, "Stop")
        finally:
            await ws.close()

    asyncio.run(press())
