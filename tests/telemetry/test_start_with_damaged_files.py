"""A real `pendant` started on a data folder full of damaged recordings serves as usual: the files it cannot
repair are moved to recordings/damaged/ with their bytes unchanged, each with a line in the event log, and a
recording cut short by a kill is finished, all while the pendant already answers."""

from __future__ import annotations

import os
from pathlib import Path

import httpx

from pendant.telemetry.mcap_scan import MAGIC
from pendant.telemetry.repair import DAMAGED, finished
from tests.support.launchers import running_pendant
from tests.support.recordings import CRAFTED, HEADER, crafted, make_recording
from tests.support.waiting import wait_until

SPARSE_BYTES = 500 * 1024 * 1024  # a header, then holes: what a power cut can leave
REPAIRED_WITHIN_S = 60.0
KILLED = "pendant-20270101-000000"


def test_the_pendant_serves_whatever_lies_in_its_recordings_folder(tmp_path: Path) -> None:
    recordings = tmp_path / "recordings"
    recordings.mkdir()
    make_recording(tmp_path / "live", 10.0, unfinished_copy=recordings / f"{KILLED}.mcap")
    files = {f"pendant-{name}": crafted(name) for name in CRAFTED}
    for stem, data in files.items():
        (recordings / f"{stem}.mcap").write_bytes(data)
    sparse = recordings / "pendant-sparse.mcap"
    sparse.write_bytes(MAGIC + HEADER)
    os.truncate(sparse, SPARSE_BYTES)

    with running_pendant("--data", str(tmp_path)) as base:
        wait_until(lambda: finished(recordings / f"{KILLED}.mcap"), REPAIRED_WITHIN_S, "the repair")
        wait_until(
            lambda: all(
                (recordings / DAMAGED / f"{stem}.mcap").exists() for stem in [*files, "pendant-sparse"]
            ),
            REPAIRED_WITHIN_S,
            "moving the damaged files aside",
        )
        said = httpx.get(f"{base}/pendant/events", params={"kind": "error", "limit": 100}, timeout=30.0)
        messages = [event["message"] for event in said.json()["events"]]
        assert httpx.get(f"{base}/robot/id", timeout=30.0).status_code == 200

    for stem, data in files.items():
        assert (recordings / DAMAGED / f"{stem}.mcap").read_bytes() == data, stem
        assert any(f"Recording {stem} could not be repaired" in m for m in messages), (stem, messages)
    moved = recordings / DAMAGED / "pendant-sparse.mcap"
    assert moved.stat().st_size == SPARSE_BYTES
    with moved.open("rb") as stream:
        assert stream.read(len(MAGIC + HEADER) + 16) == MAGIC + HEADER + bytes(16)
    assert any(f"Recording {KILLED} was not finished" in m and "repaired" in m for m in messages), messages
