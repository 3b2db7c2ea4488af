"""Every save a version: the programs folder is a git repository that dulwich and the `git` binary both read,
with the operator as author and the change in words as the message; restore brings back a version's bytes."""

from __future__ import annotations

from pathlib import Path

from dulwich.objects import Commit
from dulwich.repo import Repo

from pendant.program import MoveStep, ProgramRunner, ProgramWorkspace, WaitStep
from pendant.program.history import COMMITTER, OUTSIDE
from pendant.program.versions import VersionedStore
from tests.support.program_history import git, pick_program, waypoint

OPERATOR = "browser #2 (10.0.0.7)"


def workspace_in(folder: Path, runner: ProgramRunner, who: str = OPERATOR) -> ProgramWorkspace:
    return ProgramWorkspace(VersionedStore(folder, who=lambda: who), runner)


def test_three_saves_are_three_commits_that_dulwich_and_git_read(
    tmp_path: Path, runner: ProgramRunner
) -> None:
    folder = tmp_path / "programs"
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")
    workspace.replace_step(0, MoveStep(waypoint="P1", speed=40.0))
    workspace.save()
    workspace.insert_step(WaitStep(ms=250), after=4)
    workspace.save()

    subjects = git(folder, "log", "--format=%an|%s").splitlines()
    assert subjects[:3] == [
        f"{OPERATOR}|Save pick: step 6 (Wait 250 ms) added",
        f"{OPERATOR}|Save pick: step 1 (Move J to P1 @ 40%): speed 20 -> 40 %",
        f"{OPERATOR}|Save pick: new program, 4 steps, 3 waypoints",
    ]
    assert subjects[3].startswith(f"{COMMITTER}|Start the history")  # the folder's .gitignore
    assert git(folder, "status", "--porcelain") == ""  # the autosave is ignored, the index agrees
    assert (folder / ".autosave.json").is_file()
    assert ".autosave.json" not in git(folder, "ls-files")

    versions = workspace.versions.versions("pick")
    assert [v.commit for v in versions] == git(folder, "log", "--format=%H", "--", "pick.json").split()
    assert all(v.who == OPERATOR for v in versions)
    repo = Repo(str(folder))
    try:
        newest = repo[repo.head()]
        assert isinstance(newest, Commit)
        assert newest.author.decode().startswith(f"{OPERATOR} <")
        # The whole diff is in the message, one change a line, and who saved it.
        assert b"- step 6 (Wait 250 ms) added" in newest.message and OPERATOR.encode() in newest.message
    finally:
        repo.close()
    # The committed file is the file on disk, byte for byte.
    assert git(folder, "show", "HEAD:pick.json").encode() == (folder / "pick.json").read_bytes()


def test_restore_brings_back_a_versions_bytes_as_a_new_version_and_undo_goes_back(
    tmp_path: Path, runner: ProgramRunner
) -> None:
    folder = tmp_path / "programs"
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")
    saved = workspace.program  # as the file holds it (floats rounded)
    first_bytes = (folder / "pick.json").read_bytes()
    first = workspace.versions.versions("pick")[0]
    workspace.replace_step(0, MoveStep(waypoint="P1", speed=60.0))
    workspace.save()
    edited = workspace.program

    workspace.restore_version(first.short)
    assert (folder / "pick.json").read_bytes() == first_bytes
    assert workspace.program == saved and not workspace.dirty
    log = git(folder, "log", "--format=%s", "--", "pick.json").splitlines()
    assert log[0] == f"Restore pick to version {first.short} of {first.time:%Y-%m-%d %H:%M} UTC"
    assert len(log) == 3  # nothing rewritten: the speed-60 version is still there
    assert git(folder, "status", "--porcelain") == ""

    workspace.undo()  # the program that was on screen, as unsaved changes to the restored file
    assert workspace.program == edited and workspace.dirty and workspace.file_name == "pick"
    workspace.redo()
    assert workspace.program == saved and not workspace.dirty


def test_delete_is_a_version_and_the_deleted_program_can_still_be_read(
    tmp_path: Path, runner: ProgramRunner
) -> None:
    folder = tmp_path / "programs"
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")
    saved, version = workspace.program, workspace.versions.versions("pick")[0]
    workspace.delete_file("pick")

    versions = workspace.versions.versions("pick")
    assert versions[0].summary == "Delete pick" and versions[0].deleted
    assert not (folder / "pick.json").exists()
    assert workspace.versions.version_program("pick", version.commit) == saved


def test_a_file_changed_behind_the_pendants_back_is_kept_before_it_is_replaced(
    tmp_path: Path, runner: ProgramRunner
) -> None:
    folder = tmp_path / "programs"
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")
    by_hand = (folder / "pick.json").read_text().replace('"ms": 500', '"ms": 750')
    (folder / "pick.json").write_text(by_hand)

    workspace.replace_step(1, MoveStep(waypoint="P2", speed=30.0))
    workspace.save()

    note = workspace.versions.history_note
    assert note is not None and "changed outside the pendant" in note and "kept in the history" in note
    versions = workspace.versions.versions("pick")
    assert [v.who for v in versions] == [OPERATOR, OUTSIDE, OPERATOR]
    assert workspace.versions.version_bytes("pick", versions[1].commit) == by_hand.encode()
    # The save is described against the hand-edited file it replaced: the wait went back to 500 ms.
    assert "step 5 (Wait 500 ms): wait 750 -> 500 ms" in git(folder, "log", "-1", "--format=%B")


def test_a_repository_the_user_made_is_used_as_it_is(tmp_path: Path, runner: ProgramRunner) -> None:
    folder = tmp_path / "programs"
    folder.mkdir()
    git(folder, "init", "-q")
    (folder / "README.md").write_text("our cell's programs\n")
    git(folder, "add", "README.md")
    git(folder, "-c", "user.name=Ada", "-c", "user.email=ada@example.com", "commit", "-qm", "Our repo")
    (folder / "notes.txt").write_text("staged, not committed\n")
    git(folder, "add", "notes.txt")

    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")

    assert git(folder, "log", "--format=%an|%s").splitlines() == [
        f"{OPERATOR}|Save pick: new program, 4 steps, 3 waypoints",
        "Ada|Our repo",
    ]
    assert not (folder / ".gitignore").exists()  # their repository, their rules
    # Their staged work stays staged and out of the pendant's commit; the autosave is not staged.
    assert sorted(git(folder, "status", "--porcelain").splitlines()) == ["?? .autosave.json", "A  notes.txt"]
    assert git(folder, "show", "--name-only", "--format=", "HEAD").split() == ["pick.json"]


def test_programs_already_in_the_folder_start_the_history(tmp_path: Path, runner: ProgramRunner) -> None:
    folder = tmp_path / "programs"
    folder.mkdir()
    (folder / "old.json").write_bytes(b"kept as it was\n")  # not even a program: kept all the same
    other = pick_program().model_copy(
        update={"waypoints": (waypoint("P1", 1.0), *pick_program().waypoints[1:])}
    )
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(other)
    workspace.save_as("pick")

    first = git(folder, "log", "--reverse", "--format=%s").splitlines()[0]
    assert first == "Start the history of this programs folder (1 program in it)"
    assert git(folder, "show", "HEAD~1:old.json") == "kept as it was\n"
    assert set(git(folder, "ls-files").split()) == {".gitignore", "old.json", "pick.json"}


def test_the_folder_pushes_to_a_server_with_ordinary_git(tmp_path: Path, runner: ProgramRunner) -> None:
    folder = tmp_path / "programs"
    workspace = workspace_in(folder, runner)
    workspace.open_uploaded(pick_program())
    workspace.save_as("pick")
    workspace.replace_step(0, MoveStep(waypoint="P1", speed=45.0))
    workspace.save()
    assert "error" not in git(folder, "fsck", "--full", "--strict").lower()

    server = tmp_path / "server.git"
    git(tmp_path, "init", "-q", "--bare", str(server))
    git(folder, "push", "-q", str(server), "HEAD:refs/heads/main")
    clone = tmp_path / "clone"
    git(tmp_path, "clone", "-q", "--branch", "main", str(server), str(clone))
    assert (clone / "pick.json").read_bytes() == (folder / "pick.json").read_bytes()
    assert (
        git(clone, "log", "-1", "--format=%an|%s")
        == f"{OPERATOR}|Save pick: step 1 (Move J to P1 @ 45%): speed 20 -> 45 %\n"
    )
