"""Two processes saving the same program at the same moment, round after round: every save that returned is
a version reachable in the history (read back with the `git` binary), and none says it was not recorded."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from pendant.program.versions import VersionedStore
from tests.support.launchers import child_env
from tests.support.program_history import git, pick_program

ROUNDS = 20
WRITERS = 2
START_DELAY_S = 3.0  # both writers are imported and waiting when the first round starts
WRITER_TIMEOUT_S = 120.0

WRITER = """
import json, sys, time
from pendant.program import WaitStep
from pendant.program.versions import VersionedStore
folder, writer, rounds, start_at = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
store = VersionedStore(folder, who=lambda: f"writer {writer}")
program = store.load("pick")
time.sleep(max(0.0, start_at - time.time()))
for round in range(rounds):
    marker = 100_000 + writer * 1000 + round
    store.save(program.model_copy(update={"steps": (WaitStep(ms=marker),)}), "pick")
    print(json.dumps({"marker": marker, "note": store.history_note}), flush=True)
"""


def reachable_contents(folder: Path) -> list[str]:
    """pick.json as each commit reachable from HEAD holds it."""
    commits = git(folder, "rev-list", "HEAD", "--", "pick.json").split()
    return [git(folder, "show", f"{commit}:pick.json") for commit in commits]


def test_concurrent_saves_of_one_program_are_each_a_reachable_version(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    VersionedStore(folder).save(pick_program(), "pick")
    start_at = time.time() + START_DELAY_S
    writers = [
        subprocess.Popen(
            [sys.executable, "-c", WRITER, str(folder), str(n), str(ROUNDS), str(start_at)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=child_env(),
        )
        for n in range(WRITERS)
    ]
    saves = []
    for writer in writers:
        out, err = writer.communicate(timeout=WRITER_TIMEOUT_S)
        assert writer.returncode == 0, err
        saves += [json.loads(line) for line in out.splitlines()]
    assert len(saves) == WRITERS * ROUNDS
    assert [s for s in saves if s["note"] is not None] == [], "a save that was not recorded"
    versions = reachable_contents(folder)
    lost = [s["marker"] for s in saves if not any(f'"ms": {s["marker"]}' in v for v in versions)]
    assert lost == [], f"{len(lost)} acknowledged saves are in no reachable version"
    assert git(folder, "fsck", "--strict") is not None
