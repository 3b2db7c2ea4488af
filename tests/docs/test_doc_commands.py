"""Every command block the docs mark runnable (a fence opened with ```sh runnable) runs as written, in bash
with `set -euo pipefail`, against a real `pendant --no-ui` on a free loopback port: the docs' $PULSE_URL
(default http://127.0.0.1:8081, make run's API) is set to it. A block that starts a server is not marked."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.support.launchers import REPO_ROOT, running_pendant
from tests.support.waiting import SAFETY_NET_S

PAGES = [REPO_ROOT / "README.md", *sorted((REPO_ROOT / "docs").glob("*.md"))]
RUNNABLE = re.compile(r"^```sh runnable\n(.*?)^```", re.M | re.S)
RUN_TIMEOUT_S = 120.0
MIN_BLOCKS = 8  # the docs' runnable blocks; fewer means the marker was lost in an edit


def runnable_blocks() -> list[tuple[str, str]]:
    return [
        (f"{page.relative_to(REPO_ROOT)}#{number}", block)
        for page in PAGES
        for number, block in enumerate(RUNNABLE.findall(page.read_text(encoding="utf-8")), start=1)
    ]


BLOCKS = runnable_blocks()


@pytest.fixture(scope="module")
def served() -> Iterator[str]:
    with running_pendant("--time-scale", "10") as url:
        yield url


def test_the_docs_still_mark_their_commands_runnable() -> None:
    assert len(BLOCKS) >= MIN_BLOCKS, [name for name, _ in BLOCKS]


@pytest.mark.parametrize("block", [block for _, block in BLOCKS], ids=[name for name, _ in BLOCKS])
def test_a_runnable_block_runs_against_a_simulator(block: str, served: str) -> None:
    httpx.put(f"{served}/sim/reset", timeout=SAFETY_NET_S).raise_for_status()
    bin_dir = str(Path(sys.executable).parent)
    env = {**os.environ, "PULSE_URL": served, "PATH": bin_dir + os.pathsep + os.environ.get("PATH", "")}
    done = subprocess.run(
        ["bash", "-c", "set -euo pipefail\n" + block],
        cwd=REPO_ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=RUN_TIMEOUT_S,
        check=False,
    )
    assert done.returncode == 0, f"{block}\n--- exit {done.returncode}:\n{done.stdout}{done.stderr}"
    assert done.stdout.strip(), f"{block}\n--- printed nothing"
