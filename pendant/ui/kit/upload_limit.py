"""Uploads from the page bounded before they are buffered.

viser (1.1.1) keeps every part of a file upload in memory until the last one arrives, whatever its declared
size, and only then hands the file to the page's callback: a viewer's 60 MB upload grew the pendant by
~90 MB before the program loader refused it (issue #16). Here the upload handlers of a GUI are wrapped so that
an upload declaring more than the limit is refused at its first message (nothing kept, the browser told why),
and one whose parts add up to more than it declared is dropped as soon as they do.

This reaches into viser's message handlers (`_websock_interface`, `_handle_file_transfer_*`,
`_current_file_upload_states`): viser has no public hook for it, and the version is pinned in pyproject.toml.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import viser
from viser import _messages

from pendant.ui.kit.commands import notify_refusal


def upload_too_large_message(max_bytes: int) -> str:
    return f"A file to upload has at most {max_bytes} bytes"


def limit_uploads(gui: viser.GuiApi, max_bytes: int) -> None:
    """Refuse uploads to `gui` larger than `max_bytes` before buffering them (idempotent per GUI)."""
    handlers: dict[type, list[Callable[..., Any]]] = gui._websock_interface._incoming_handlers
    states: dict[str, dict[str, Any]] = gui._current_file_upload_states

    def refuse_large_start(original: Callable[..., Any]) -> Callable[..., Any]:
        def on_start(client_id: int, message: _messages.FileTransferStartUpload) -> Any:
            if message.size_bytes > max_bytes or message.part_count > max_bytes:
                title = f"{message.filename} not uploaded"
                notify_refusal(_client(gui, client_id), title, upload_too_large_message(max_bytes))
                return None
            return original(client_id, message)

        return on_start

    def drop_overflowing_parts(original: Callable[..., Any]) -> Callable[..., Any]:
        def on_part(client_id: int, message: _messages.FileTransferPart) -> Any:
            state = states.get(message.transfer_uuid)
            if state is not None and state["transferred_bytes"] + len(message.content) > state["total_bytes"]:
                states.pop(message.transfer_uuid, None)  # it lied about its size: forget what it sent
                return None
            return original(client_id, message)

        return on_part

    wrappers = {
        _messages.FileTransferStartUpload: (gui._handle_file_transfer_start, refuse_large_start),
        _messages.FileTransferPart: (gui._handle_file_transfer_part, drop_overflowing_parts),
    }
    for message_type, (original, wrap) in wrappers.items():
        callbacks = handlers.get(message_type, [])
        for index, callback in enumerate(callbacks):
            if callback == original:  # not yet wrapped (a second call finds only the wrappers)
                callbacks[index] = wrap(callback)


def _client(gui: viser.GuiApi, client_id: int) -> viser.ClientHandle | None:
    owner = gui._owner
    if isinstance(owner, viser.ClientHandle):
        return owner
    return owner.get_clients().get(client_id)
