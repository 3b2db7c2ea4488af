"""A repository whose HEAD commit is cut in half: Save (of the program, and as a new name) still writes the
file and says it was not recorded in the history and why; `pendant history` answers with one line and exit 2,
no traceback."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from pendant.program import MoveStep
from pendant.program.versions import VersionedStore
from tests.support import preloaded
from tests.support.launchers import child_env
from tests.support.program_history import cut_head_commit, pick_program

EXIT_REFUSED = 2  # docs/history.md


@pytest.fixture
def damaged(tmp_path: Path) -> VersionedStore:
    store = VersionedStore(tmp_path / "programs")
    store.save(pick_program(), "pick")
    store.save(pick_program(speed=40.0), "pick")
    cut_head_commit(store.folder)
    return store


@pytest.mark.parametrize("name", ["pick", "pick copy"])
def test_a_save_into_a_damaged_history_writes_the_file_and_says_why_not_recorded(
    damaged: VersionedStore, name: str
) -> None:
    program = pick_program().model_copy(update={"steps": (MoveStep(waypoint="P1", speed=70.0),)})
    damaged.save(program, name)
    assert damaged.load(name).steps == program.steps
    note = damaged.history_note
    assert note is not None and f"{name}.json was saved, but not recorded in the history: " in note, note
    assert "damaged" in note or "could not be written" in note
    assert "git fsck" in note and "\n" not in note


def test_pendant_history_on_a_damaged_repository_says_so_in_one_line(damaged: VersionedStore) -> None:
    done = preloaded.run(
        [sys.executable, "-m", "pendant", "history", "pick", "--programs", str(damaged.folder)],
        capture_output=True,
        text=True,
        timeout=60,
        env=child_env(),
    )
    assert done.returncode == EXIT_REFUSED, done.stderr
    assert done.stdout == ""
    [line] = done.stderr.splitlines()
    assert line.startswith("pendant history: The history in ") and "damaged" in line and "git fsck" in line
