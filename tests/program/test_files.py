"""Program files: atomic writes, refused files change nothing, names cannot leave the folder, autosave."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from pydantic import ValidationError

from pendant.controller import Point, Pose, Position, Rotation
from pendant.program import (
    SCHEMA_VERSION,
    MoveStep,
    Program,
    ProgramFileError,
    ProgramRunner,
    ProgramStore,
    Waypoint,
    atomic_write,
    sanitize_name,
)
from pendant.sim import SimController

REPO_ROOT = Path(__file__).resolve().parents[2]


def waypoint(name: str, j1: float = 0.0) -> Waypoint:
    return Waypoint(
        name=name,
        pose=Pose(angles=[j1, -90.0, 90.0, -90.0, -90.0, 0.0]),
        position=Position(point=Point(x=0.4, y=0.1, z=0.3), rotation=Rotation(roll=3.1, pitch=0.0, yaw=0.2)),
    )


def program_of(*names: str) -> Program:
    return Program(
        name="demo",
        waypoints=tuple(waypoint(n) for n in names),
        steps=tuple(MoveStep(waypoint=n) for n in names),
    )


def test_save_and_load_round_trip_the_program(tmp_path: Path) -> None:
    store = ProgramStore(tmp_path)
    saved = store.save(program_of("P1", "P2"), "pick place")
    assert store.names() == ["pick place"]
    assert store.load("pick place") == saved
    document = json.loads((tmp_path / "pick place.json").read_text())
    assert document["schema_version"] == SCHEMA_VERSION
    assert [w["name"] for w in document["waypoints"]] == ["P1", "P2"]
    assert [s["waypoint"] for s in document["steps"]] == ["P1", "P2"]


def test_a_write_that_fails_midway_leaves_the_old_file_and_no_litter(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    store = ProgramStore(tmp_path)
    store.save(program_of("P1"), "job")
    before = (tmp_path / "job.json").read_bytes()

    def crash(*_: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", crash)
    with pytest.raises(OSError, match="disk full"):
        store.save(program_of("P1", "P2", "P3"), "job")
    assert (tmp_path / "job.json").read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["job.json"]


def test_atomic_write_replaces_the_whole_content(tmp_path: Path) -> None:
    target = tmp_path / "sub" / "file.json"
    atomic_write(target, b"x" * 10_000)
    atomic_write(target, b"short")
    assert target.read_bytes() == b"short"
    assert [p.name for p in target.parent.iterdir()] == ["file.json"]


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (b"{not json", "is not a JSON document"),
        (b"[1, 2]", "is not a program"),
        (b'{"name": "x", "steps": []}', "no schema_version"),
        (
            json.dumps({"schema_version": SCHEMA_VERSION + 1, "steps": []}).encode(),
            "written by a newer pendant",
        ),
        (
            json.dumps({"schema_version": 1, "steps": [{"kind": "teleport"}]}).encode(),
            "is not a valid program",
        ),
        (json.dumps({"schema_version": 1, "steps": [{"kind": "wait", "ms": -5}]}).encode(), "is not a valid"),
        (
            json.dumps({"schema_version": 0, "steps": []}).encode(),
            "schema version 0, which no pendant writes",
        ),
        (
            json.dumps({"schema_version": -3, "steps": []}).encode(),
            "schema version -3, which no pendant writes",
        ),
    ],
)
def test_a_bad_file_is_refused_with_a_clear_message_and_nothing_is_overwritten(
    tmp_path: Path, content: bytes, reason: str
) -> None:
    store = ProgramStore(tmp_path)
    (tmp_path / "bad.json").write_bytes(content)
    with pytest.raises(ProgramFileError, match=reason):
        store.load("bad")
    assert (tmp_path / "bad.json").read_bytes() == content


@pytest.mark.parametrize("name", ["../escape", "a/b", "..", ".hidden", "", "   ", "x\\y", "nul\0", "é" * 3])
def test_names_that_would_leave_the_folder_or_hide_are_refused(tmp_path: Path, name: str) -> None:
    with pytest.raises(ProgramFileError):
        ProgramStore(tmp_path).save(program_of("P1"), name)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("version", [0, -1])
def test_a_program_below_schema_version_1_cannot_be_made(version: int) -> None:
    with pytest.raises(ValidationError, match="greater than or equal to 1"):
        Program(schema_version=version)
    with pytest.raises(ValidationError):
        Program.model_validate({"schema_version": version, "steps": []})


def test_names_are_trimmed_and_lose_their_json_suffix() -> None:
    assert sanitize_name("  pick-place_2.json ") == "pick-place_2"


def test_the_autosave_is_not_listed_and_restores_the_program(tmp_path: Path) -> None:
    store = ProgramStore(tmp_path)
    store.autosave(program_of("P1"), None, True)
    assert store.names() == []
    restored = store.restore()
    assert restored is not None
    program, file_name, dirty = restored
    assert program.waypoint_names() == ["P1"] and file_name is None and dirty
    assert store.restore_problem is None


def refused_autosaves(folder: Path) -> list[Path]:
    return sorted(folder.glob(".autosave.refused.*.json"))


def test_a_corrupt_autosave_starts_an_empty_program_and_every_refused_one_is_kept_and_explained(
    tmp_path: Path, runner: ProgramRunner
) -> None:
    from pendant.program import ProgramWorkspace

    folder = tmp_path / "programs"
    folder.mkdir()
    (folder / ".autosave.json").write_text("{garbage")
    store = ProgramStore(folder)
    workspace = ProgramWorkspace(store, runner)
    assert workspace.program.steps == () and not workspace.dirty
    [first] = refused_autosaves(folder)
    assert first.read_text() == "{garbage"
    assert not (folder / ".autosave.json").exists()
    problem = store.restore_problem
    assert problem is not None
    assert "could not be restored" in problem and "not a JSON document" in problem
    assert first.name in problem and "empty program" in problem
    assert store.names() == []  # kept aside, not offered as a program

    # A second refusal, in the same second, keeps both.
    newer = {"file_name": "job", "dirty": True, "program": {"schema_version": SCHEMA_VERSION + 1}}
    (folder / ".autosave.json").write_text(json.dumps(newer))
    restarted = ProgramStore(folder)
    assert ProgramWorkspace(restarted, runner).program.steps == ()
    assert first.read_text() == "{garbage"
    kept = refused_autosaves(folder)
    assert len(kept) == 2
    [second] = [p for p in kept if p != first]
    assert json.loads(second.read_text()) == newer
    assert restarted.restore_problem is not None and "newer pendant" in restarted.restore_problem
    assert second.name in restarted.restore_problem


@pytest.mark.parametrize(
    ("content", "reason"),
    [
        (b"[1, 2]", "not an autosave"),
        (b'{"file_name": null, "dirty": true}', "not an autosave"),
        (json.dumps({"program": {"schema_version": 0}}).encode(), "schema version 0"),
    ],
)
def test_an_autosave_that_is_not_one_is_refused_with_the_reason(
    tmp_path: Path, content: bytes, reason: str
) -> None:
    (tmp_path / ".autosave.json").write_bytes(content)
    store = ProgramStore(tmp_path)
    assert store.restore() is None
    assert store.restore_problem is not None and reason in store.restore_problem
    assert [p.read_bytes() for p in refused_autosaves(tmp_path)] == [content]


def test_an_autosave_that_cannot_be_moved_aside_is_left_and_the_message_says_to_copy_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / ".autosave.json").write_text("{garbage")

    def read_only(*_: object) -> None:
        raise PermissionError("read-only folder")

    monkeypatch.setattr(os, "link", read_only)
    monkeypatch.setattr(os, "rename", read_only)
    store = ProgramStore(tmp_path)
    assert store.restore() is None
    assert (tmp_path / ".autosave.json").read_text() == "{garbage"
    assert store.restore_problem is not None
    assert "read-only folder" in store.restore_problem and "copy" in store.restore_problem


def test_no_autosave_is_no_problem(tmp_path: Path) -> None:
    store = ProgramStore(tmp_path)
    assert store.restore() is None and store.restore_problem is None


def test_a_recorded_waypoint_survives_the_process_being_killed(tmp_path: Path) -> None:
    """Record in a pendant process that is then killed (SIGKILL: no cleanup runs); a new one has it back."""
    script = textwrap.dedent(f"""
        import os, signal
        from pendant.controller import Point, Pose, Position, Rotation
        from pendant.program import ProgramRunner, ProgramStore, ProgramWorkspace
        workspace = ProgramWorkspace(ProgramStore({str(tmp_path)!r}), ProgramRunner(controller=None))
        position = Position(point=Point(x=0.4, y=0.1, z=0.3), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0))
        workspace.record(Pose(angles=[10.0, -90.0, 90.0, -90.0, -90.0, 0.0]), position)
        os.kill(os.getpid(), signal.SIGKILL)
    """)
    killed = subprocess.run([sys.executable, "-c", script], cwd=REPO_ROOT, timeout=60, check=False)
    assert killed.returncode == -9

    from pendant.program import ProgramRunner, ProgramWorkspace

    restarted = ProgramWorkspace(ProgramStore(tmp_path), ProgramRunner(SimController()))
    assert restarted.program.waypoint_names() == ["P1"]
    assert restarted.program.waypoint("P1").pose.angles[0] == 10.0
    assert restarted.dirty


@pytest.mark.parametrize("depth", [17, 5000])
def test_steps_nested_too_deeply_are_refused_with_a_message(tmp_path: Path, depth: int) -> None:
    # Written as text: json.dumps itself cannot nest 5,000 deep.
    steps = '{"kind": "loop", "times": 1, "body": [' * depth + "]}" * depth
    (tmp_path / "deep.json").write_text(f'{{"schema_version": 2, "name": "deep", "steps": [{steps}]}}')
    with pytest.raises(ProgramFileError, match="nest"):
        ProgramStore(tmp_path).load("deep")
