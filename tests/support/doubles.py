"""Stand-ins for a browser: what the pendant uses of a viser ClientHandle, and viser's way of calling back."""

from __future__ import annotations

import asyncio
import inspect
from dataclasses import dataclass, field
from typing import Any, Literal, cast

import numpy as np
import viser
import viser.transforms as vtf
from viser import _messages as viser_messages

from pendant.ui.jog.panel import HOLD_CONFIRM_HZ
from pendant.ui.kit.typed_field import TypedField

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

    @property
    def handle(self) -> viser.ClientHandle:
        """This stand-in where the pendant takes a viser ClientHandle: it has what the pendant uses of one."""
        return cast(viser.ClientHandle, self)


def committed(handle: Any, value: Any) -> tuple[Any, Any]:
    """A typed field (pendant/ui/kit/typed_field.py) gets the text the page commits: its text box, and a
    number as typed ("80.0"), a vector as "x, y, z", a string as it is."""
    if not isinstance(handle, TypedField):
        return handle, value
    if isinstance(value, tuple | list):
        value = ", ".join(repr(float(v)) for v in value)
    elif value is not None and not isinstance(value, str):
        value = repr(float(value))
    return handle.handle, value


def event(handle: Any, browser: FakeBrowser | None) -> viser.GuiEvent:
    """viser's event for `handle` from `browser` (None: from the server's Python, as on_click's callers see
    it when no browser is involved)."""
    if browser is None:
        return viser.GuiEvent(client=None, client_id=0, target=handle)
    return viser.GuiEvent(client=browser.handle, client_id=browser.client_id, target=handle)


def fire(handle: Any, browser: FakeBrowser | None, value: Any = None) -> None:
    """What viser does when a browser clicks or edits `handle`: set the value, call the callbacks once."""
    handle, value = committed(handle, value)
    if value is not None:
        handle._impl.value = value  # not `handle.value = ...`: that calls back as from Python (client None)
    for callback in list(handle._impl.update_cb):
        called = callback(event(handle, browser))
        if inspect.iscoroutine(called):  # viser awaits it on its event loop (a stop button: kit/stop_path.py)
            asyncio.run(called)


def confirm_hold(button: viser.GuiButtonHandle, browser: FakeBrowser) -> None:
    """One of the calls viser makes, HOLD_CONFIRM_HZ times a second, while a browser holds `button` (viser
    awaits an async callback on its event loop; the controller work it hands to a thread is waited for)."""
    for callback in list(button._button_impl.hold_cbs_from_freq[HOLD_CONFIRM_HZ]):
        result = callback(event(button, browser))
        if inspect.iscoroutine(result):
            asyncio.run(result)


def drag(handle: viser.TransformControlsHandle, browser: FakeBrowser, path: list[np.ndarray]) -> None:
    """What viser does for a browser's drag of a gizmo: the pose of every move (4x4 each), phases start,
    update…, end."""

    def send(phase: Literal["start", "update", "end"]) -> None:
        event = viser.TransformControlsEvent(
            client=browser.handle,
            client_id=browser.client_id,
            target=handle,
            phase=phase,
        )
        for callback in list(handle._impl_aux.update_cb):
            result = callback(event)
            if inspect.iscoroutine(result):
                asyncio.run(result)

    send("start")
    for T in path:
        handle._impl.position = T[:3, 3].copy()
        handle._impl.wxyz = vtf.SO3.from_matrix(T[:3, :3]).wxyz
        send("update")
    send("end")


def upload_states(button: viser.GuiUploadButtonHandle) -> tuple[str, dict[str, Any]]:
    """The upload button's id on the websocket, and viser's uploads in progress (what it keeps in memory)."""
    return button._impl.uuid, button._impl.gui_api._current_file_upload_states
