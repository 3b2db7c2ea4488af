"""A 500 MB recording downloaded from the page: the pendant sends it a part at a time as the browser takes
them, so its memory hardly grows (the issue measured 251 -> 1,381 MB for one click before). A real pendant
process, a bare websocket for the browser (it keeps a hash of the parts, not the parts), the recording a
sparse file with distinct blocks, put in the recordings folder after the start (the start-up repair never
reads it)."""

from __future__ import annotations

import asyncio
import contextlib
import hashlib
from pathlib import Path

import pytest
import zstandard

from tests.support.big_recordings import write_sparse_file
from tests.support.headless_viewer import click_message, find_button, next_messages, open_viewer
from tests.support.launchers import running_pendant_ui

# In front (`alone`): the pendant lets a browser go that has not answered its pings for ~4 s, and behind the
# timed pass at nice 19 this client, hashing 500 MB, went that long without a CPU (CI, 1 Dec).
pytestmark = [pytest.mark.slow, pytest.mark.alone]

SIZE = 500 * 1024 * 1024
RSS_GROWTH_MAX = 50 * 1024 * 1024  # the bound for a 500 MB download
PAGE_TIMEOUT_S = 60.0
DOWNLOAD_TIMEOUT_S = 300.0
SETTLE_S = 2.0  # the new browser's panels built and sent before the baseline is read
NAME = "pendant-20260101-000000.mcap"


def rss(pid: int) -> int:
    """The process's resident memory, bytes (/proc)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise AssertionError("no VmRSS")


def file_hash(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as file:
        while chunk := file.read(1024 * 1024):
            digest.update(chunk)
    return digest.hexdigest()


async def download(port: int, pid: int) -> tuple[str, str, int, int]:
    """Click Download MCAP; the file's name, the hash of the bytes received, the RSS before the click and
    the highest RSS read while the parts came."""
    ws = await open_viewer(port)
    try:
        button = await find_button(ws, "Download MCAP", PAGE_TIMEOUT_S)
        zstd = zstandard.ZstdDecompressor()
        async with asyncio.timeout(SETTLE_S * 2):  # the rest of the panels: read, and let them go
            deadline = asyncio.get_running_loop().time() + SETTLE_S
            while asyncio.get_running_loop().time() < deadline:
                with contextlib.suppress(TimeoutError):  # websockets' recv may be cancelled safely
                    await asyncio.wait_for(next_messages(ws, zstd), SETTLE_S / 4)
        before = peak = rss(pid)
        await ws.send(click_message(button))
        digest, name, count, received = hashlib.sha256(), "", -1, 0
        async with asyncio.timeout(DOWNLOAD_TIMEOUT_S):
            while received != count:
                for message in await next_messages(ws, zstd):
                    if message.get("type") == "FileTransferStartDownload":
                        name, count = message["filename"], message["part_count"]
                    elif message.get("type") == "FileTransferPart":
                        assert message["part_index"] == received, "the parts come in order"
                        digest.update(message["content"])
                        received += 1
                peak = max(peak, rss(pid))
        return name, digest.hexdigest(), before, peak
    finally:
        await ws.close()


def test_a_500_mb_recording_downloads_without_the_pendant_holding_it(tmp_path: Path) -> None:
    data = tmp_path / "data"
    (data / "recordings").mkdir(parents=True)
    with running_pendant_ui(env={"PENDANT_DATA_DIR": str(data)}) as pendant:
        assert pendant.process is not None
        path = write_sparse_file(data / "recordings" / NAME, SIZE)
        name, received, before, peak = asyncio.run(download(pendant.ui_port, pendant.process.pid))
    assert name == NAME
    assert received == file_hash(path), "the browser got the file's bytes"
    growth = peak - before
    assert growth < RSS_GROWTH_MAX, f"the pendant grew by {growth / 1e6:.0f} MB for a 500 MB download"
