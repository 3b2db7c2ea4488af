"""A program upload from the page is bounded before it is buffered (issue #16, finding 5): a viewer's 60 MB
upload used to be kept whole in memory before the loader refused it. A real websocket client on loopback
sends viser's upload messages, as the page's upload button (or a modified page) would."""

from __future__ import annotations

import asyncio
import json
import time
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

import msgspec
import pytest
import viser
import websockets

from pendant.sim import MonotonicClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import upload_states
from tests.support.headless_viewer import CAMERA_HELLO
from tests.support.pages import new_page
from tests.support.ports import free_port
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S
PART_BYTES = 1024 * 1024
HUGE_PARTS = 60  # 60 MB, as in the audit


@pytest.fixture
def page(tmp_path: Path) -> Iterator[tuple[PendantUI, int]]:
    port = free_port()
    sim = SimController("pulse75", MonotonicClock())
    ui = new_page(sim, sim.arm, port=port, mode_line="sim", programs_dir=str(tmp_path))
    ui.start()
    yield ui, port
    ui.stop()


def start_message(button_uuid: str, transfer: str, filename: str, size: int, parts: int) -> bytes:
    return msgspec.msgpack.encode(
        {
            "type": "FileTransferStartUpload",
            "source_component_uuid": button_uuid,
            "transfer_uuid": transfer,
            "filename": filename,
            "mime_type": "application/json",
            "part_count": parts,
            "size_bytes": size,
        }
    )


def part_message(button_uuid: str, transfer: str, index: int, content: bytes) -> bytes:
    return msgspec.msgpack.encode(
        {
            "type": "FileTransferPart",
            "source_component_uuid": button_uuid,
            "transfer_uuid": transfer,
            "part_index": index,
            "content": content,
        }
    )


async def wait_for(condition: Callable[[], bool], timeout_s: float = WAIT_S) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "did not happen in time"
        await asyncio.sleep(0.05)


def test_an_upload_larger_than_a_program_is_refused_before_it_is_kept(page: tuple[PendantUI, int]) -> None:
    ui, port = page
    protocol = [websockets.Subprotocol(f"viser-v{viser.__version__}")]
    program = json.dumps({"schema_version": 1, "name": "x", "steps": [{"kind": "wait", "ms": 10}]}).encode()

    async def scenario() -> None:
        async with websockets.connect(
            f"ws://127.0.0.1:{port}/", subprotocols=protocol, max_queue=None, open_timeout=SAFETY_NET_S
        ) as ws:
            await ws.send(CAMERA_HELLO)
            await wait_for(lambda: len(ui.sessions) == 1)
            session: ClientSession = next(iter(ui.sessions.values()))
            button = session.program.file_section.upload
            button_uuid, states = upload_states(button)

            # Declared too large: refused at the first message, none of its parts kept (all but the last
            # are sent, so without the limit they would wait in memory for it).
            huge = str(uuid.uuid4())
            await ws.send(start_message(button_uuid, huge, "huge.json", HUGE_PARTS * PART_BYTES, HUGE_PARTS))
            for index in range(HUGE_PARTS - 1):
                await ws.send(part_message(button_uuid, huge, index, b" " * PART_BYTES))
            # Declared small, sent large: dropped as soon as the parts pass what it declared.
            liar = str(uuid.uuid4())
            await ws.send(start_message(button_uuid, liar, "liar.json", 10, 3))
            await ws.send(part_message(button_uuid, liar, 0, b" " * PART_BYTES))
            await wait_for(lambda: liar not in states)
            await ws.send(part_message(button_uuid, liar, 1, b" " * PART_BYTES))
            # A program of ordinary size still uploads.
            ok = str(uuid.uuid4())
            await ws.send(start_message(button_uuid, ok, "ok.json", len(program), 1))
            await ws.send(part_message(button_uuid, ok, 0, program))
            await wait_for(lambda: len(ui.programs.program.steps) == 1)  # handled in order: all before too
            assert states == {}

    asyncio.run(scenario())
