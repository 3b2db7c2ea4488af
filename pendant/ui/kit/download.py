"""A file sent to one browser in parts, each read as the connection takes the one before.

viser's `send_file_download` takes the whole file as bytes and queues every 1 MB part at once: a 500 MB
recording cost 1.1 GB of memory for one click. Here at most two parts wait in the browser's queue; the
next is read from disk once viser's sender has taken the one before (its cursor in the queue, a private
field of viser 1.1.1, checked by tests/ui/test_download_stream.py). A browser that leaves, or takes no
part for STALL_S, ends the download.
"""

from __future__ import annotations

import mimetypes
import time
import uuid
from collections.abc import Iterator
from pathlib import Path

import viser
from viser import _messages
from viser.infra._async_message_buffer import AsyncMessageBuffer

PART_BYTES = 1024 * 1024  # viser's own part size
QUEUED_PARTS = 2  # parts waiting in the browser's queue at most
STALL_S = 30.0
POLL_S = 0.005


class DownloadStopped(Exception):
    """The browser left, or stopped taking parts."""


def send_file(client: viser.ClientHandle, path: Path, name: str | None = None) -> int:
    """Send `path` to `client` as a download (saved at once); the bytes sent."""
    size = path.stat().st_size
    with path.open("rb") as file:
        parts = iter(lambda: file.read(PART_BYTES), b"")
        return _send(client, name or path.name, size, parts)


def send_bytes(client: viser.ClientHandle, name: str, content: bytes) -> int:
    """Send `content` to `client` as a download, a part at a time (no copy of the whole)."""
    view = memoryview(content)
    parts = (bytes(view[i : i + PART_BYTES]) for i in range(0, len(content), PART_BYTES))
    return _send(client, name, len(content), parts)


def _send(client: viser.ClientHandle, name: str, size: int, parts: Iterator[bytes]) -> int:
    connection = client._websock_connection  # the browser's own queue (viser 1.1.1)
    queue = connection.get_message_buffer()
    transfer = str(uuid.uuid4())
    count = -(-size // PART_BYTES)
    connection.queue_message(
        _messages.FileTransferStartDownload(
            save_immediately=True,
            transfer_uuid=transfer,
            filename=name,
            mime_type=mimetypes.guess_type(name, strict=False)[0] or "application/octet-stream",
            part_count=count,
            size_bytes=size,
        )
    )
    queued: list[int] = []  # each part's place in the queue (at least)
    sent = 0
    for index, part in enumerate(parts):
        if index >= count:
            break  # the file grew while it was read: the browser expects `count` parts
        if len(queued) >= QUEUED_PARTS:
            _wait_taken(queue, client.client_id, queued.pop(0))
        connection.queue_message(_messages.FileTransferPart(None, transfer, index, part))
        queued.append(queue.message_counter - 1)
        client.flush()
        sent += len(part)
    return sent


def _wait_taken(queue: AsyncMessageBuffer, client_id: int, place: int) -> None:
    """Until viser's sender has taken the message at `place` off the browser's queue."""
    cursors = queue.generator_cursors
    last, since = cursors.get(client_id, -1), time.monotonic()
    while (cursor := cursors.get(client_id, -1)) < place:
        if queue.done:
            raise DownloadStopped("the browser left")
        if cursor != last:
            last, since = cursor, time.monotonic()
        elif time.monotonic() - since > STALL_S:
            raise DownloadStopped(f"the browser took nothing for {STALL_S:.0f} s")
        time.sleep(POLL_S)
