"""Faults of the host, with a real `pendant --no-ui` process: a data folder it may not write still lets it
start (the event log in memory, said in one line with what to do); a disk that fills up mid-run loses events
that /metrics counts; temporary files orphaned by a crash are removed on start, fresh ones left alone."""

from __future__ import annotations

import contextlib
import os
import resource
import subprocess
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

import httpx
import pytest

from tests.support.launchers import REPO_ROOT
from tests.support.metrics import scrape, values
from tests.support.ports import LOOPBACK, free_port
from tests.support.waiting import SAFETY_NET_S, wait_until

# Root writes anywhere: without these capabilities (util-linux's setpriv) it meets the folder's permissions.
WITHOUT_OVERRIDES = ["setpriv", "--bounding-set=-dac_override,-dac_read_search,-fowner", "--"]
FILE_SIZE_LIMIT_BYTES = 256 * 1024  # "the disk is full" for the process, through RLIMIT_FSIZE
REACHABLE_POSE = {"angles": [10.0, -90.0, 90.0, -90.0, -90.0, 0.0]}

pytestmark = pytest.mark.slow  # real pendant processes


@contextlib.contextmanager
def pendant(
    tmp_path: Path, *args: str, preexec: Callable[[], None] | None = None, wrapper: Sequence[str] = ()
) -> Iterator[tuple[str, Path]]:
    """A `pendant --no-ui` on a free port; yields its URL and the file its stderr goes to."""
    port = free_port()
    stderr_path = tmp_path / f"stderr-{port}.txt"
    command = [
        *wrapper,
        sys.executable,
        "-m",
        "pendant",
        "--no-ui",
        "--host",
        LOOPBACK,
        "--api-port",
        str(port),
    ]
    command += args
    with stderr_path.open("w") as stderr:
        process = subprocess.Popen(
            command, cwd=REPO_ROOT, stdout=subprocess.DEVNULL, stderr=stderr, preexec_fn=preexec
        )
    base = f"http://{LOOPBACK}:{port}"
    try:
        wait_until(
            lambda: process.poll() is None and httpx.get(f"{base}/robot/id", timeout=1.0).status_code == 200,
            what=f"the pendant answering (stderr: {stderr_path})",
        )
        yield base, stderr_path
    finally:
        process.terminate()
        try:
            process.wait(SAFETY_NET_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(SAFETY_NET_S)


def test_a_read_only_data_folder_starts_with_the_log_in_memory_and_one_clear_line(tmp_path: Path) -> None:
    data = tmp_path / "data"
    data.mkdir(mode=0o555)
    programs = tmp_path / "programs"
    wrapper = WITHOUT_OVERRIDES if os.geteuid() == 0 else []
    with pendant(tmp_path, "--data", str(data), "--programs", str(programs), wrapper=wrapper) as (
        base,
        stderr,
    ):
        said = stderr.read_text()
        lines = [line for line in said.splitlines() if "event log" in line]
        assert len(lines) == 1, said
        assert str(data) in lines[0] and "in memory" in lines[0] and "Fix:" in lines[0]
        assert "Traceback" not in said
        assert (
            httpx.put(f"{base}/pose?speed=20", json=REACHABLE_POSE, timeout=SAFETY_NET_S).status_code == 200
        )
        events = httpx.get(f"{base}/pendant/events", timeout=SAFETY_NET_S).json()["events"]
        assert any(e["message"] == "PUT /pose -> 200" for e in events), "the log still works, in memory"
        metrics = scrape(base)
        assert values(metrics, "pendant_event_log_on_disk") == [0.0]
    assert list(data.iterdir()) == [], "nothing written where it may not be"


def test_a_disk_that_fills_up_loses_events_and_says_how_many(tmp_path: Path) -> None:
    def small_disk() -> None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (FILE_SIZE_LIMIT_BYTES, FILE_SIZE_LIMIT_BYTES))

    with pendant(tmp_path, "--data", str(tmp_path / "data"), preexec=small_disk) as (base, stderr):
        assert values(scrape(base), "pendant_events_dropped_total") == [0.0]
        with httpx.Client(timeout=SAFETY_NET_S) as client:
            deadline = time.monotonic() + 120
            dropped = 0.0
            while dropped == 0.0 and time.monotonic() < deadline:
                for _ in range(50):  # each command is an event; each event a write
                    client.put(f"{base}/signal/output/1/high")
                dropped = values(scrape(base), "pendant_events_dropped_total")[0]
            assert dropped > 0, "the events that never reached the disk are counted"
            assert client.get(f"{base}/robot/id").status_code == 200, "the pendant goes on"
        said = stderr.read_text()
        assert "could not be written" in said and "Fix:" in said
        assert said.count("could not be written") == 1, "one line for the failures, not one per event"


def test_temporary_files_orphaned_by_a_crash_are_removed_on_start(tmp_path: Path) -> None:
    programs = tmp_path / "programs"
    programs.mkdir()
    orphan = programs / ".Pick.json.k3j2l1.tmp"
    fresh = programs / ".Place.json.a8b7c6.tmp"  # another pendant may be writing this one right now
    kept = programs / "Pick.json"
    for path in (orphan, fresh, kept):
        path.write_text("{}")
    an_hour_ago = time.time() - 3600
    os.utime(orphan, (an_hour_ago, an_hour_ago))
    os.utime(kept, (an_hour_ago, an_hour_ago))
    with pendant(tmp_path, "--programs", str(programs), "--data", str(tmp_path / "data")) as (_, stderr):
        assert not orphan.exists() and fresh.exists() and kept.exists()
        assert str(orphan) in stderr.read_text()
