"""Every stop holds a held jog still while a classroom watches (issues 22 and 37). A real `pendant` process on
loopback; the operator (the first browser: it has control) holds J1+ over the page's hold line, a
confirmation every 50 ms as the page's worker sends them, and 30 viewers in a process of their own read every
frame of the page (tests/support/room.py).

Each stop comes while the arm moves: the page's Freeze and Protective stop (the operator's clicks on viser's
websocket, the same one the 30 viewers load), and the API's PUT /freeze and POST /stop over real HTTP. The
operator's button stays down (confirmations keep coming, messages already on their way); the arm must
stop and stay still. After a protective stop, a new press does not move it either: only Recover (`PUT
/recover` here) lifts it. Then a new press moves again."""

from __future__ import annotations

import asyncio
import contextlib
import time
from collections.abc import AsyncIterator, Awaitable, Callable

import pytest
import websockets

from tests.support.headless_viewer import (
    HOLD_HZ,
    JogPad,
    click_message,
    drain,
    gui_update,
    line_hold,
    line_release,
    open_hold_line,
    open_viewer,
    read_jog_pad,
)
from tests.support.launchers import Pendant, running_pendant_ui
from tests.support.room import Room
from tests.support.waiting import wait_until

pytestmark = [pytest.mark.slow, pytest.mark.measures]  # a hold confirmed every 50 ms beside 30 viewers

VIEWERS = 30
JOG_SPEED_PERCENT = 5.0  # J1 at 6 deg/s: four stops' worth of jogging stays far from its limits
PAGE_TIMEOUT_S = 120.0  # generous: every viewer's whole panel on a loaded machine; not what is tested
MOVING_DEG = 0.5  # the held jog is under way once J1 has gone this far
MOVE_TIMEOUT_S = 10.0
STOP_TIMEOUT_S = 5.0  # a safety net (how fast a stop is: tests/browser/test_stop_path.py)
STILL_DEG = 0.01  # the simulator holds a stopped arm exactly
SETTLED_S = 0.3  # two poses this far apart, the same: the arm has stopped
HELD_S = 1.5  # the button kept down after the stop, confirming all along
FREEZE, PROTECTIVE_STOP = "Freeze", "Protective stop"


async def confirming(line: websockets.ClientConnection, pad: JogPad) -> None:
    """The button held: a confirmation every 1 / HOLD_HZ s until cancelled."""
    while True:
        await line.send(line_hold(pad.hold))
        await asyncio.sleep(1.0 / HOLD_HZ)


def j1(pendant: Pendant) -> float:
    return float(pendant.pose()[0])


def settled(pendant: Pendant) -> float:
    """J1 once two poses SETTLED_S apart agree (within STOP_TIMEOUT_S, or AssertionError)."""
    last = [j1(pendant)]

    def still() -> bool:
        time.sleep(SETTLED_S)
        now = j1(pendant)
        was, last[0] = last[0], now
        return abs(now - was) < STILL_DEG

    wait_until(still, STOP_TIMEOUT_S, "the arm to stop")
    return last[0]


@contextlib.asynccontextmanager
async def held(line: websockets.ClientConnection, pad: JogPad) -> AsyncIterator[None]:
    """J1+ pressed and kept down for the block, then released."""
    task = asyncio.create_task(confirming(line, pad))
    try:
        yield
    finally:
        task.cancel()
        with contextlib.suppress(asyncio.CancelledError):
            await task
        await line.send(line_release(pad.hold))


async def moves(pendant: Pendant, line: websockets.ClientConnection, pad: JogPad) -> bool:
    """A new press moves J1 (by MOVING_DEG within MOVE_TIMEOUT_S)."""
    start = await asyncio.to_thread(j1, pendant)
    async with held(line, pad):
        until = time.monotonic() + MOVE_TIMEOUT_S
        while time.monotonic() < until:
            if await asyncio.to_thread(j1, pendant) > start + MOVING_DEG:
                return True
            await asyncio.sleep(0.1)
    return False


async def travel_while_pressed(
    pendant: Pendant, line: websockets.ClientConnection, pad: JogPad, seconds: float
) -> float:
    """How far J1 goes while a new press is held for `seconds` (deg)."""
    start = await asyncio.to_thread(j1, pendant)
    async with held(line, pad):
        await asyncio.sleep(seconds)
    return abs(await asyncio.to_thread(j1, pendant) - start)


async def stops_and_stays(
    pendant: Pendant,
    line: websockets.ClientConnection,
    pad: JogPad,
    name: str,
    send: Callable[[], Awaitable[object]],
) -> None:
    """Held and moving, the stop `send`s; the arm stops and stays still while the button stays down."""
    start = await asyncio.to_thread(j1, pendant)
    async with held(line, pad):
        await asyncio.to_thread(
            wait_until, lambda: j1(pendant) > start + MOVING_DEG, MOVE_TIMEOUT_S, f"the jog before {name}"
        )
        await send()
        stopped_at = await asyncio.to_thread(settled, pendant)
        await asyncio.sleep(HELD_S)  # the button still down, confirming
        after = await asyncio.to_thread(j1, pendant)
        assert abs(after - stopped_at) < STILL_DEG, (
            f"{name}: J1 went from {stopped_at:.3f} to {after:.3f} deg while the button stayed down"
        )


async def _every_stop_beside_viewers(pendant: Pendant) -> dict[str, str]:
    """Each stop in turn on a held jog, 30 viewers watching; the motion state each left."""
    operator = await open_viewer(pendant.ui_port)
    pad = await read_jog_pad(operator, PAGE_TIMEOUT_S, buttons=(FREEZE, PROTECTIVE_STOP))
    draining = asyncio.create_task(drain(operator))
    await operator.send(gui_update(pad.speed, JOG_SPEED_PERCENT))
    line = await open_hold_line(pad)
    room = Room(pendant.ui_port, VIEWERS, PAGE_TIMEOUT_S)
    stops: dict[str, Callable[[], Awaitable[object]]] = {
        f"the page's {FREEZE}": lambda: operator.send(click_message(pad.buttons[FREEZE])),
        f"the page's {PROTECTIVE_STOP}": lambda: operator.send(click_message(pad.buttons[PROTECTIVE_STOP])),
        "PUT /freeze": lambda: asyncio.to_thread(lambda: pendant.api.put("/freeze").raise_for_status()),
        "POST /stop": lambda: asyncio.to_thread(lambda: pendant.api.post("/stop").raise_for_status()),
    }
    left: dict[str, str] = {}
    try:
        await asyncio.to_thread(room.open)
        for name, send in stops.items():
            await stops_and_stays(pendant, line, pad, name, send)
            left[name] = await asyncio.to_thread(pendant.status)
            if left[name] == "ERROR":
                travel = await travel_while_pressed(pendant, line, pad, HELD_S)
                assert travel < STILL_DEG, (
                    f"after {name}, a new press moved J1 {travel:.3f} deg without Recover"
                )
                (await asyncio.to_thread(pendant.api.put, "/recover")).raise_for_status()
            assert await moves(pendant, line, pad), f"after {name} (and Recover), a new press did not jog"
    finally:
        await asyncio.to_thread(room.close)
        draining.cancel()
        await line.close()
        await operator.close()
    return left


def test_every_stop_holds_a_held_jog_still_while_30_viewers_watch() -> None:
    with running_pendant_ui() as pendant:
        left = asyncio.run(_every_stop_beside_viewers(pendant))
    assert left == {
        f"the page's {FREEZE}": "IDLE",
        f"the page's {PROTECTIVE_STOP}": "ERROR",
        "PUT /freeze": "IDLE",
        "POST /stop": "ERROR",
    }
