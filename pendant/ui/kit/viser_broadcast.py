"""A broadcast serialised once for all browsers, not once per browser (issue 37).

viser 1.1.1 sends every browser its windows of the shared (broadcast) messages from a producer task per
browser (`viser.infra._infra._message_producer`), and each producer turns the same messages into a dict,
msgpack and zstd itself: with 60 viewers of a moving arm (about ten scene messages a tick at 30 Hz) that took
most of viser's event loop, and viewers got 10-13 frames a second. Here a broadcast message is serialised
once (its msgpack bytes kept and embedded as they are, msgspec.Raw), and a window that several browsers get
alike (the usual case: they all wake on the same message) is compressed once. The frames are byte for byte
what viser would send, but for the window's `timestampSec`, which the page does not read.

Only the broadcast buffer's messages (viser creates each once and never changes it after it is queued) are
kept; a browser's own messages and any message carrying binary arrays (meshes, a newcomer's replay) go the
old way. Not public API: `installed()` says whether viser had the expected shape; if not, nothing is
replaced and viser serialises per browser as before (tests/test_reached_into.py fails by name).
"""

from __future__ import annotations

import inspect
import logging
import time
from collections import OrderedDict
from collections.abc import Callable, Sequence
from typing import Any

import msgspec
import viser.infra._infra as infra
import zstandard
from viser.infra._async_message_buffer import AsyncMessageBuffer
from viser.infra._messages import Message

log = logging.getLogger(__name__)

PRODUCER_PARAMETERS = ["websocket", "buffer", "client_id", "backlog_done_message"]
KEPT_MESSAGES = 4096  # the last few seconds of a moving arm's messages: every browser's windows among them
KEPT_WINDOWS = 64

_viser_producer: Callable[..., Any] = infra._message_producer
_messages: OrderedDict[int, tuple[Message, bytes | None]] = OrderedDict()  # id -> (message, msgpack or None)
_windows: OrderedDict[tuple[int, ...], tuple[Sequence[Message], bytes]] = OrderedDict()
_zstd = zstandard.ZstdCompressor(level=1)


def _encoded(message: Message) -> bytes | None:
    """The message's msgpack, made once; None when it carries binary arrays (serialised with its window)."""
    kept = _messages.get(id(message))
    if kept is not None and kept[0] is message:  # kept alive here, so its id is still its own
        _messages.move_to_end(id(message))
        return kept[1]
    binaries: list[memoryview] = []
    as_dict = message.as_serializable_dict(binaries)
    encoded = None if binaries else msgspec.msgpack.encode(as_dict)
    _messages[id(message)] = (message, encoded)
    if len(_messages) > KEPT_MESSAGES:
        _messages.popitem(last=False)
    return encoded


def broadcast_frame(outgoing: Sequence[Message]) -> bytes:
    """viser's wire frame of one window of broadcast messages (see `_message_producer` in viser's _infra)."""
    key = tuple(id(message) for message in outgoing)
    kept = _windows.get(key)
    if kept is not None and all(a is b for a, b in zip(kept[0], outgoing, strict=True)):
        _windows.move_to_end(key)
        return kept[1]
    binaries: list[memoryview] = []
    messages = []
    for message in outgoing:
        encoded = _encoded(message)
        messages.append(
            msgspec.Raw(encoded) if encoded is not None else message.as_serializable_dict(binaries)
        )
    inner = msgspec.msgpack.encode(
        {
            "messages": messages,
            "timestampSec": time.perf_counter(),
            "binaryBufferLengths": tuple(b.nbytes for b in binaries),
        }
    )
    compressed = _zstd.compress(inner)
    parts: list[bytes | memoryview] = [
        len(inner).to_bytes(8, "little"),
        len(compressed).to_bytes(8, "little"),
        compressed,
    ]
    infra._append_aligned_buffers(parts, binaries, 16 + len(compressed))
    frame = b"".join(parts)
    if not binaries:  # a replay's meshes go to one newcomer: not kept
        _windows[key] = (tuple(outgoing), frame)
        if len(_windows) > KEPT_WINDOWS:
            _windows.popitem(last=False)
    return frame


async def _message_producer(
    websocket: Any,
    buffer: AsyncMessageBuffer,
    client_id: int,
    backlog_done_message: Message | None = None,
) -> None:
    """viser's producer, with the broadcast buffer's frames from `broadcast_frame` (on viser's event loop:
    every producer runs there, so the caches above are touched by one thread only)."""
    if not buffer.persistent_messages:  # a browser's own messages: its own, once anyway
        await _viser_producer(websocket, buffer, client_id, backlog_done_message)
        return
    windows = buffer.window_generator(client_id, backlog_done_message=backlog_done_message)
    try:
        while not buffer.done:
            try:
                outgoing = await windows.__anext__()
            except StopAsyncIteration:
                break
            await websocket.send(broadcast_frame(outgoing))
    finally:
        await windows.aclose()  # as viser's: the buffer's cursor for this browser is released now


def viser_has_the_expected_shape() -> bool:
    return (
        list(inspect.signature(_viser_producer).parameters) == PRODUCER_PARAMETERS
        and callable(getattr(infra, "_append_aligned_buffers", None))
        and "_message_producer(" in inspect.getsource(infra.WebsockServer._background_worker)
    )


def serialise_broadcasts_once() -> bool:
    """Install the producer above (idempotent); False (viser left as it is) if viser changed shape."""
    if infra._message_producer is _message_producer:
        return True
    try:
        if not viser_has_the_expected_shape():
            log.warning("viser changed: each browser's broadcast is serialised on its own, as viser does")
            return False
    except (OSError, TypeError, ValueError):  # no source to read (a frozen install)
        return False
    infra._message_producer = _message_producer  # type: ignore[assignment]
    return True
