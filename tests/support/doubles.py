"""Stand-ins for a browser: what the pendant uses of a viser ClientHandle, and viser's way of calling back."""

from __future__ import annotations

import asyncio
import inspect
from dataclasses import dataclass, field
from typing import Any

import viser
from viser import _messages as viser_messages

OPERATOR, VIEWER = 1, 2  # client ids: on loopback the first browser to join is the operator


class _SentAtOnce:
    """A browser's message queue as pendant.ui.kit.download sees it, every message taken at once."""

    def __init__(self) -> None:
        self.generator_cursors: dict[int, int] = {}
        self.message_counter = 0
        self.done = False


class _Connection:
    """A browser's websocket as pendant.ui.kit.download writes to it: the parts of a download put together."""

    def __init__(self, browser: FakeBrowser) -> None:
        self._browser = browser
        self._queue = _SentAtOnce()
        self._files: dict[str, tuple[str, int, list[bytes]]] = {}

    def get_message_buffer(self) -> _SentAtOnce:
        return self._queue

    def queue_message(self, message: object) -> None:
        self._queue.message_counter += 1
        self._queue.generator_cursors[self._browser.client_id] = self._queue.message_counter - 1
        if isinstance(message, viser_messages.FileTransferStartDownload):
            self._files[message.transfer_uuid] = (message.filename, message.part_count, [])
        elif isinstance(message, viser_messages.FileTransferPart):
            name, count, parts = self._files[message.transfer_uuid]
            assert message.part_index == len(parts), "parts in order"
            parts.append(message.content)
            if len(parts) == count:
                self._browser.downloads.append((name, b"".join(parts)))


@dataclass
class FakeBrowser:
    """Its id, and the notifications and downloads the pendant sends it (kept for the test)."""

    client_id: int
    notifications: list[str] = field(default_factory=list)
    downloads: list[tuple[str, bytes]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._websock_connection = _Connection(self)

    def add_notification(self, *, title: str, body: str, **_: object) -> None:
        self.notifications.append(f"{title}: {body}")

    def send_file_download(self, filename: str, content: bytes, **_: object) -> None:
        self.downloads.append((filename, content))

    def flush(self) -> None:
        pass


def event(handle: Any, browser: FakeBrowser) -> viser.GuiEvent:
    return viser.GuiEvent(client=browser, client_id=browser.client_id, target=handle)  # type: ignore[arg-type]  # a fake client for viser's


def fire(handle: Any, browser: FakeBrowser, value: Any = None) -> None:
    """What viser does when a browser clicks or edits `handle`: set the value, call the callbacks once."""
    if value is not None:
        handle._impl.value = value  # not `handle.value = ...`: that calls back as from Python (client None)
    for callback in list(handle._impl.update_cb):
        called = callback(event(handle, browser))
        if inspect.iscoroutine(called):  # viser awaits it on its event loop (a stop button: kit/stop_path.py)
            asyncio.run(called)
