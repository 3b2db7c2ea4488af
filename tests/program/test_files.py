"""Program files: atomic writes, refused files change nothing, names cannot leave the folder, autosave."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from pendant.controller import Point, Pose, Position, Rotation
from pendant.program import (
    SCHEMA_VERSION,
    MoveStep,
    Program,
    ProgramFileError,
    ProgramStore,
    Waypoint,
    atomic_write,
    sanitize_name,
)

REPO_ROOT = Path(__file__).resolve().parents[2]


def waypoint(name: str, j1: float = 0.0) -> Waypoint:
    return Waypoint(
        name=name,
        pose=Pose(angles=[j1, -90.0, 90.0, -90.0, -90.0, 0.0]),
        position=Position(point=Point(x=0.4, y=0.1, z=0.3), rotation=Rotation(roll=3.1, pitch=0.0, yaw=0.2)),
    )


def program_of(*names: str) -> Program:
    return Program(name="demo", steps=tuple(MoveStep(waypoint=waypoint(n)) for n in names))


def test_save_and_load_round_trip_the_program(tmp_path: Path) -> None:
    store = ProgramStore(tmp_path)
    saved = store.save(program_of("P1", "P2"), "pick place")
    assert store.names() == ["pick place"]
    assert store.load("pick place") == saved
    document = json.loads((tmp_path / "pick place.json").read_text())
    assert document["schema_version"] == SCHEMA_VERSION
    assert [s["waypoint"]["name"] for s in document["steps"]] == ["P1", "P2"]


def test_a_write_that_fails_midway_leaves_the_old_file_and_no_litter(tmp_path: Path, monkeypatch) -> None:
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


def test_names_are_trimmed_and_lose_their_json_suffix() -> None:
    assert sanitize_name("  pick-place_2.json ") == "pick-place_2"


def test_the_autosave_is_not_listed_and_an_unreadable_one_is_kept_aside(tmp_path: Path) -> None:
    store = ProgramStore(tmp_path)
    store.autosave(program_of("P1"), None, True)
    assert store.names() == []
    program, file_name, dirty = store.restore()  # type: ignore[misc]
    assert program.waypoint_names() == ["P1"] and file_name is None and dirty
    store.autosave_path.write_text("{garbage")
    assert store.restore() is None
    assert (tmp_path / ".autosave.refused.json").read_text() == "{garbage"


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

    restarted = ProgramWorkspace(ProgramStore(tmp_path), ProgramRunner(controller=None))  # type: ignore[arg-type]
    assert restarted.program.waypoint_names() == ["P1"]
    assert restarted.program.steps[0].waypoint.pose.angles[0] == 10.0  # type: ignore[union-attr]
    assert restarted.dirty
