"""A history that cannot be written never costs the save: the file is written first and the failure said.
A folder the pendant may not write is refused with a clear message and every file left as it was."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from pendant.program import MoveStep
from pendant.program.files import dump_program
from pendant.program.history import HistoryError
from pendant.program.versions import VersionedStore
from tests.support.program_history import git, pick_program

# A real process without CAP_DAC_OVERRIDE: even as root, a folder's write bits then hold (the suite runs as
# root in CI, where chmod alone would not make a folder read-only).
NO_OVERRIDE = ["setpriv", "--inh-caps=-dac_override,-dac_read_search", "--bounding-set=-dac_override"]
SAVE_SCRIPT = """
import json, sys
from pendant.program import MoveStep, ProgramFileError
from pendant.program.files import parse_program
from pendant.program.versions import VersionedStore
store = VersionedStore(sys.argv[1], who=lambda: "browser #1 (127.0.0.1)")
program = store.load("pick").model_copy(update={"steps": (MoveStep(waypoint="P1", speed=90.0),)})
try:
    store.save(program, "pick")
    print(json.dumps({"error": None, "note": store.history_note}))
except ProgramFileError as error:
    print(json.dumps({"error": str(error), "note": store.history_note}))
"""


def saved_once(folder: Path) -> VersionedStore:
    store = VersionedStore(folder, who=lambda: "browser #1 (127.0.0.1)")
    store.save(pick_program(), "pick")
    return store


def save_without_override(folder: Path) -> dict[str, str | None]:
    done = subprocess.run(
        [*NO_OVERRIDE, sys.executable, "-c", SAVE_SCRIPT, str(folder)],
        capture_output=True,
        text=True,
        timeout=60,
        env=os.environ,
    )
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def faster(program_speed: float) -> MoveStep:
    return MoveStep(waypoint="P1", speed=program_speed)


def test_a_read_only_folder_refuses_the_save_clearly_and_keeps_the_file(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    saved_once(folder)
    before = (folder / "pick.json").read_bytes()
    commits = git(folder, "rev-list", "--all")
    folder.chmod(0o555)
    try:
        answer = save_without_override(folder)
    finally:
        folder.chmod(0o755)
    assert answer["error"] is not None
    assert "pick.json could not be saved" in answer["error"] and "read-only" in answer["error"]
    assert (folder / "pick.json").read_bytes() == before
    assert git(folder, "rev-list", "--all") == commits


def test_a_read_only_history_keeps_the_save_and_says_it_was_not_recorded(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    saved_once(folder)
    subprocess.run(["chmod", "-R", "a-w", str(folder / ".git")], check=True)
    try:
        answer = save_without_override(folder)
    finally:
        subprocess.run(["chmod", "-R", "u+w", str(folder / ".git")], check=True)
    assert answer["error"] is None
    assert (
        answer["note"] is not None
        and "pick.json was saved, but not recorded in the history" in answer["note"]
    )
    assert b'"speed": 90.0' in (folder / "pick.json").read_bytes()  # the save itself is on disk


def test_a_damaged_repository_keeps_the_save_and_says_what_to_do(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    store = saved_once(folder)
    branch = git(folder, "symbolic-ref", "HEAD").strip()
    (folder / ".git" / branch).write_text(
        "0123456789abcdef0123456789abcdef01234567\n"
    )  # a commit that is not there

    edited = pick_program().model_copy(update={"steps": (faster(70.0),)})
    store.save(edited, "pick")
    assert store.load("pick").steps == (faster(70.0),)
    assert store.history_note is not None
    assert "damaged" in store.history_note and "git fsck" in store.history_note
    with pytest.raises(HistoryError, match="damaged"):
        store.versions("pick")


def test_a_git_folder_that_is_not_a_repository_keeps_the_save(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    folder.mkdir()
    (folder / ".git").write_text("this is not a repository\n")
    store = VersionedStore(folder)
    store.save(pick_program(), "pick")
    assert store.load("pick").steps == pick_program().steps
    assert store.history_note is not None and "not recorded in the history" in store.history_note
    assert ".git" in store.history_note


def test_a_repository_in_the_middle_of_a_merge_is_not_committed_to(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    store = saved_once(folder)
    head = git(folder, "rev-parse", "HEAD").strip()
    (folder / ".git" / "MERGE_HEAD").write_text(head + "\n")

    store.save(pick_program().model_copy(update={"steps": (faster(55.0),)}), "pick")
    assert store.load("pick").steps == (faster(55.0),)
    assert store.history_note is not None and "in the middle of a merge" in store.history_note
    assert git(folder, "rev-parse", "HEAD").strip() == head


def test_a_version_that_is_not_there_is_refused_clearly(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    store = saved_once(folder)
    with pytest.raises(HistoryError, match="No version 'abcdef12'"):
        store.restore_version("pick", "abcdef12")
    with pytest.raises(HistoryError, match="No version"):
        store.version_program("pick", "../../etc")
    assert store.load("pick") == VersionedStore(folder).load("pick")


def test_a_file_that_is_not_a_program_is_kept_and_the_save_described_as_new(tmp_path: Path) -> None:
    folder = tmp_path / "programs"
    store = saved_once(folder)
    (folder / "pick.json").write_bytes(b"{ broken by hand")
    store.save(pick_program(), "pick")
    log = git(folder, "log", "--format=%an|%s", "--", "pick.json").splitlines()
    assert log[0].endswith("|Save pick: new program, 4 steps, 3 waypoints")
    assert log[1] == "outside the pendant|pick.json as found in the folder (changed outside the pendant)"
    assert git(folder, "show", "HEAD~1:pick.json") == "{ broken by hand"
    assert (folder / "pick.json").read_bytes() == dump_program(store.load("pick"))
