"""The page's stops never wait for viser's callback pool (issue 32): with every one of its 32 threads held
(as 40 slow clicks held them), a browser that connects still gets Freeze, and Freeze, Esc, Protective stop
and the program's Pause and Stop still act; so do the API's PUT /freeze and POST /stop, over real HTTP,
against a motion under way and against a program the page runs, in a still step before an output step or
in a motion; and so do a browser's Freeze, Esc and Protective stop against such a run. The page in-process
on loopback, the simulator on a fake clock (its move stays RUNNING until something stops
it) or, for the program, the real one; browsers as bare websockets (what a browser sends)."""

from __future__ import annotations

import asyncio
import contextlib
import threading
from collections.abc import Callable, Iterator

import httpx
import msgspec
import pytest
import websockets
import zstandard

from pendant.api.app import create_app
from pendant.controller import MotionParams, MotionStatus, Pose
from pendant.sim import MonotonicClock, SimController
from pendant.ui.app import PendantUI
from tests.support import run_stops
from tests.support.doubles import OPERATOR
from tests.support.headless_viewer import click_message, drain, next_messages, open_viewer
from tests.support.pages import pendant_page
from tests.support.threads import serve_in_thread
from tests.support.waiting import wait_until

VISER_POOL = 32  # viser 1.1.1's callback pool (ViserServer._thread_executor)
PAGE_TIMEOUT_S = 30.0  # generous: the machine may be loaded; nothing here measures speed
STOP_TIMEOUT_S = 60.0  # a safety net: a stop that waited for the held pool would never come
AWAY = Pose(angles=[120.0, -60.0, 60.0, -90.0, -90.0, 0.0])


@contextlib.contextmanager
def page_with_its_pool_held(sim: SimController) -> Iterator[PendantUI]:
    """A page whose viser callback pool is busy with 32 callbacks that do not end (until the caller's do)."""
    with pendant_page(sim, sim.arm) as page:
        release = threading.Event()
        for _ in range(VISER_POOL + 8):
            page.server._thread_executor.submit(release.wait)
        try:
            yield page
        finally:
            release.set()


@pytest.fixture
def held_pool(sim: SimController) -> Iterator[PendantUI]:
    with page_with_its_pool_held(sim) as page:
        yield page


@contextlib.contextmanager
def its_api(page: PendantUI, sim: SimController) -> Iterator[httpx.Client]:
    """The page's API served beside it over real HTTP, its stops on the page's stop bus (as `pendant`)."""
    app = create_app(sim, stops=page.stops)
    with serve_in_thread(app) as url, httpx.Client(base_url=url, timeout=STOP_TIMEOUT_S) as api:
        yield api


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


# The page's stops, as a browser sends them: the control (as `controls` names it), its message, the state
# it leaves a motion in, how a run names the stop.
PAGE_STOPS: dict[str, tuple[str, Callable[[str], bytes], MotionStatus, str]] = {
    "Freeze": ("Freeze", click_message, MotionStatus.IDLE, "Freeze by browser #"),
    "Esc": ("command Freeze", trigger, MotionStatus.IDLE, "Freeze (Esc) by browser #"),
    "Protective stop": ("Protective stop", click_message, MotionStatus.ERROR, "Protective stop by browser #"),
}


async def press_stops(page: PendantUI, sim: SimController) -> None:
    ws = await open_viewer(page.server.get_port())
    try:
        found = await controls(ws, {label for label, *_ in PAGE_STOPS.values()})
        for stop, (label, message, after, _) in PAGE_STOPS.items():
            moving(sim)
            await ws.send(message(found[label]))
            await asyncio.to_thread(stops, sim, after, stop)
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


# The API's stops: how each is sent, the state it leaves a motion in, and how a run names it.
API_STOPS: dict[str, tuple[Callable[[httpx.Client], httpx.Response], MotionStatus, str]] = {
    "PUT /freeze": (lambda api: api.put("/freeze"), MotionStatus.IDLE, "Freeze from the API (127.0.0.1)"),
    "POST /stop": (
        lambda api: api.post("/stop"),
        MotionStatus.ERROR,
        "Protective stop from the API (127.0.0.1)",
    ),
}


@pytest.mark.parametrize("stop", API_STOPS)
def test_the_apis_stop_halts_a_motion_with_the_pool_held(
    held_pool: PendantUI, sim: SimController, stop: str
) -> None:
    send, after, _ = API_STOPS[stop]
    with its_api(held_pool, sim) as api:
        moving(sim)
        send(api).raise_for_status()
        stops(sim, after, stop)


HELD_S = 1.5


@pytest.mark.parametrize("step", ["wait", "gripper", "motion"])
@pytest.mark.parametrize("stop", API_STOPS)
def test_the_apis_stop_ends_a_run_in_a_still_step_before_an_output_with_the_pool_held(
    stop: str, step: str
) -> None:
    """A run in a still step (the gripper closing, a wait) or a motion with the pool held: the API's stop
    ends it naming the API, the arm stays put and the step after it (DO2 HIGH) never runs."""
    send, _, cause = API_STOPS[stop]
    sim = SimController("pulse75", MonotonicClock())  # the real clock: the step lasts until the stop
    with page_with_its_pool_held(sim) as page, its_api(page, sim) as api:
        page.desk.join(OPERATOR)
        run_stops.stop_the_run(
            page,
            sim,
            step,
            lambda: send(api).raise_for_status(),
            cause,
            held_s=HELD_S,
            timeout_s=STOP_TIMEOUT_S,
        )
        page.programs.stop()


async def stop_the_run_from_a_browser(page: PendantUI, sim: SimController, step: str, stop: str) -> None:
    """A browser connected to the page sends `stop` 0.3 s into `step` (run_stops.stop_the_run)."""
    label, message, _, cause = PAGE_STOPS[stop]
    ws = await open_viewer(page.server.get_port())
    reading: asyncio.Task[None] | None = None
    try:
        uuid = (await controls(ws, {label}))[label]
        reading = asyncio.create_task(drain(ws))  # a browser reads on: viser never waits for it
        loop = asyncio.get_running_loop()

        def send() -> None:
            asyncio.run_coroutine_threadsafe(ws.send(message(uuid)), loop).result(STOP_TIMEOUT_S)

        await asyncio.to_thread(
            run_stops.stop_the_run,
            page,
            sim,
            step,
            send,
            cause,
            held_s=HELD_S,
            timeout_s=STOP_TIMEOUT_S,
        )
    finally:
        await ws.close()
        if reading is not None:
            await reading


@pytest.mark.parametrize("step", ["wait", "gripper", "motion"])
@pytest.mark.parametrize("stop", PAGE_STOPS)
def test_a_browsers_stop_ends_a_run_in_a_still_step_or_a_motion_with_the_pool_held(
    stop: str, step: str
) -> None:
    """As the API's stops above, from a browser's websocket: its Freeze, Esc and Protective stop end the
    run naming the browser, the arm stays put and DO2 is never set, with every thread of the pool busy."""
    sim = SimController("pulse75", MonotonicClock())
    with page_with_its_pool_held(sim) as page:
        page.desk.join(OPERATOR)
        asyncio.run(stop_the_run_from_a_browser(page, sim, step, stop))
        page.programs.stop()
