"""A browser's side of viser's websocket, without a browser: what it sends first (its camera: viser counts a
client as connected only once it has), how it reads viser's frames, and how its page holds a jog button
(pendant/ui/page/client_page.js)."""

from __future__ import annotations

import asyncio
import contextlib
import re
import time
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field
from typing import Any

import msgspec
import viser
import websockets
import zstandard

from tests.support.waiting import SAFETY_NET_S

HOLD_HZ = 20.0  # client_page.js HOLD_HZ
JOG_PAD_J1_PLUS = re.compile(r'data-jog-uuid="([0-9a-f-]+)" aria-label="J1\+"')
JOG_STOP = re.compile(r'data-jog-stop="([0-9a-f-]+)"')
JOG_LINE = re.compile(r'data-jog-line="(\d+) ([A-Za-z0-9_-]+)"')  # the hold line: "PORT KEY"


def camera_report(
    position: Sequence[float],
    size: tuple[int, int],
    look_at: Sequence[float] = (0.0, 0.0, 0.35),
    fov_rad: float = 1.0,
) -> bytes:
    """The page's ViewerCameraMessage: where its camera is, what it looks at, how big its view is (px)."""
    width, height = size
    return msgspec.msgpack.encode(
        {
            "type": "ViewerCameraMessage",
            "wxyz": (1.0, 0.0, 0.0, 0.0),
            "position": tuple(float(v) for v in position),
            "fov": fov_rad,
            "near": 0.01,
            "far": 100.0,
            "image_height": height,
            "image_width": width,
            "look_at": tuple(float(v) for v in look_at),
            "up_direction": (0.0, 0.0, 1.0),
        }
    )


CAMERA_HELLO = camera_report((1.1, -1.3, 0.9), (1400, 900))


def decode_window(frame: bytes, zstd: zstandard.ZstdDecompressor) -> list[dict[str, Any]]:
    """One websocket frame of viser's: [u64 inner size][u64 compressed size][zstd msgpack][binary buffers]."""
    inner_size = int.from_bytes(frame[0:8], "little")
    compressed_size = int.from_bytes(frame[8:16], "little")
    inner = zstd.decompress(frame[16 : 16 + compressed_size], max_output_size=inner_size)
    messages: list[dict[str, Any]] = msgspec.msgpack.decode(inner)["messages"]
    return messages


async def open_viewer(port: int, hello: bytes = CAMERA_HELLO) -> websockets.ClientConnection:
    """A websocket to the page on `port`, as a browser opens it: viser's subprotocol, then its camera."""
    ws = await websockets.connect(
        f"ws://127.0.0.1:{port}/",
        subprotocols=[websockets.Subprotocol(f"viser-v{viser.__version__}")],
        max_queue=None,
        max_size=None,
        open_timeout=SAFETY_NET_S,
    )
    await ws.send(hello)
    return ws


def gui_update(uuid: str, value: object) -> bytes:
    """What the page sends when a control changes (a slider, a click on a hidden button)."""
    return msgspec.msgpack.encode({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"value": value}})


def hold_message(uuid: str, hz: float = HOLD_HZ) -> bytes:
    """A jog button's "still held" confirmation, as client_page.js's worker sends it (HOLD_HZ a second)."""
    return msgspec.msgpack.encode({"type": "GuiButtonHoldMessage", "uuid": uuid, "frequency": hz})


@dataclass
class JogPad:
    """The uuids a page needs to hold J1+ (the pad's markup, pendant/ui/jog/pad.py) and to set the speed."""

    hold: str
    stop: str
    speed: str
    line: tuple[int, str] | None = None  # the browser's hold line (pendant/ui/kit/hold_line.py): port, key
    buttons: dict[str, str] = field(default_factory=dict)  # label -> uuid, of those asked for


async def read_jog_pad(
    ws: websockets.ClientConnection, timeout_s: float, buttons: Collection[str] = ()
) -> JogPad:
    """Read the page's messages until its jog pad and speed box have come, and the buttons so labelled (a
    click at once may come before the button's handler: `find_button` waits for the whole panel). The pad
    is added empty and then given its markup: when viser sends a window between the two, the markup comes
    in an update (probably why a clean clone's test_hold_beside_viewers once waited 120 s for its pad)."""
    zstd = zstandard.ZstdDecompressor()
    hold = stop = speed = ""
    line: tuple[int, str] | None = None
    labelled: dict[str, str] = {}
    async with asyncio.timeout(timeout_s):
        while not (hold and speed and labelled.keys() >= set(buttons)):
            for message in await next_messages(ws, zstd):
                props = message.get("props", {})
                if message.get("type") == "GuiButtonMessage" and props.get("label") in buttons:
                    labelled.setdefault(str(props["label"]), str(message["uuid"]))
                if message.get("type") == "GuiTextMessage" and props.get("label") == "Speed %" and not speed:
                    speed = message["uuid"]
                content = str(props.get("content", "")) + str(message.get("updates", {}).get("content", ""))
                if (pad := JOG_PAD_J1_PLUS.search(content)) and (pad_stop := JOG_STOP.search(content)):
                    hold, stop = pad.group(1), pad_stop.group(1)
                    if found := JOG_LINE.search(content):
                        line = (int(found.group(1)), found.group(2))
    return JogPad(hold, stop, speed, line, labelled)


async def open_hold_line(pad: JogPad, host: str = "127.0.0.1") -> websockets.ClientConnection:
    """The hold line the page's worker opens (client_page.js): it sends `line_hold` and `line_release`."""
    assert pad.line is not None, "the jog pad names no hold line"
    port, key = pad.line
    return await websockets.connect(
        f"ws://{host}:{port}/?key={key}", compression=None, open_timeout=SAFETY_NET_S
    )


async def drain(ws: websockets.ClientConnection) -> None:
    """Read and drop whatever the page sends until it closes (a browser that reads, so viser never waits)."""
    with contextlib.suppress(websockets.ConnectionClosed):
        async for _ in ws:
            pass


def line_hold(uuid: str) -> str:
    """A confirmation over the hold line."""
    return f"hold {uuid}"


def line_release(uuid: str) -> str:
    """A press's release (its button's uuid) or cancel (the pad's stop uuid) over the hold line."""
    return f"release {uuid}"


def click_message(uuid: str) -> bytes:
    """What the page sends when a button is clicked."""
    return gui_update(uuid, True)


async def next_messages(
    ws: websockets.ClientConnection, zstd: zstandard.ZstdDecompressor
) -> list[dict[str, Any]]:
    """The messages of the next frame viser sends."""
    frame = await ws.recv()
    assert isinstance(frame, bytes)
    return decode_window(frame, zstd)


async def find_button(ws: websockets.ClientConnection, label: str, timeout_s: float) -> str:
    """Read the page's messages until a button labelled `label` has come and the whole panel with it (its
    last tab, the Dashboard's plots), as a user first sees the page laid out; its uuid. viser drops a click
    on a button that has no handler yet, and the builder gives it one just after the button: a click sent
    the moment the button showed was lost beside the timed tests, in the idle class."""
    zstd = zstandard.ZstdDecompressor()
    found: str | None = None
    whole_panel = False
    async with asyncio.timeout(timeout_s):
        while found is None or not whole_panel:
            for message in await next_messages(ws, zstd):
                kind = message.get("type")
                if kind == "GuiButtonMessage" and message["props"].get("label") == label and found is None:
                    found = str(message["uuid"])
                whole_panel = whole_panel or kind == "GuiUplotMessage"
    return found


def notification(message: dict[str, Any]) -> str | None:
    """ "Title: body" of a notification the page shows, or None for any other message."""
    if message.get("type") != "NotificationShowMessage":
        return None
    return f"{message['props']['title']}: {message['props']['body']}"


STATE_NODE = "/tcp_frame"  # its position is set on every refresh tick while the arm moves


@dataclass
class ViewerCounts:
    """What a steady viewer received: when the arm's pose came (monotonic s), GUI updates, bytes."""

    state_times: list[float] = field(default_factory=list)
    gui_updates: int = 0
    bytes_received: int = 0
    frames: int = 0  # websocket frames (viser's windows of messages)
    whole_panel: asyncio.Event = field(default_factory=asyncio.Event)  # its last tab (the Dashboard's plots)


async def viewer(url: str, counts: ViewerCounts, stop: asyncio.Event) -> None:
    """A steady viewer until `stop`: opens the page's websocket as a browser does and reads every frame."""
    protocol = [websockets.Subprotocol(f"viser-v{viser.__version__}")]
    zstd = zstandard.ZstdDecompressor()
    async with websockets.connect(
        url, subprotocols=protocol, max_queue=None, max_size=None, open_timeout=SAFETY_NET_S
    ) as ws:
        await ws.send(CAMERA_HELLO)
        while not stop.is_set():
            try:
                frame = await asyncio.wait_for(ws.recv(), timeout=0.5)
            except TimeoutError:
                continue
            assert isinstance(frame, bytes)
            counts.bytes_received += len(frame)
            counts.frames += 1
            now = time.monotonic()
            for message in decode_window(frame, zstd):
                kind = message.get("type")
                if kind == "SetPositionMessage" and message.get("name") == STATE_NODE:
                    counts.state_times.append(now)
                elif kind == "GuiUpdateMessage":
                    counts.gui_updates += 1
                elif kind == "GuiUplotMessage":
                    counts.whole_panel.set()
