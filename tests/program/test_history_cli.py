"""`pendant diff` and `pendant history`, run as the user runs them: a separate process on real files."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from pendant.program import LoopStep, MoveStep, WaitStep
from pendant.program.files import ProgramStore
from pendant.program.versions import VersionedStore
from tests.support import preloaded
from tests.support.program_history import pick_program, waypoint

EXIT_REFUSED = 2


def pendant(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return preloaded.run(
        [sys.executable, "-m", "pendant", *args],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=cwd,
        env={**os.environ, "PENDANT_PROGRAMS_DIR": str(cwd or Path.cwd())},
    )


def test_pendant_diff_of_two_files_says_what_changed(tmp_path: Path) -> None:
    old, new = pick_program(), pick_program(speed=40.0, loop_times=5)
    table = (*new.waypoints[:2], waypoint("P3", 488.0))
    ProgramStore(tmp_path).save(old, "A")
    ProgramStore(tmp_path).save(new.model_copy(update={"waypoints": table}), "B")

    done = pendant("diff", str(tmp_path / "A.json"), str(tmp_path / "B.json"))
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == [
        "P3 moved -12.0 mm in X",
        "step 1 (Move J to P1 @ 40%): speed 20 -> 40 %",
        "step 4 (Loop 5 times): now 5 times (was 3)",
    ]
    same = pendant("diff", str(tmp_path / "A.json"), str(tmp_path / "A.json"))
    assert (same.returncode, same.stdout) == (0, "No changes.\n")


def test_pendant_history_lists_the_versions_and_diff_reads_them(tmp_path: Path) -> None:
    store = VersionedStore(tmp_path / "programs", who=lambda: "browser #3 (10.0.0.9)")
    store.save(pick_program(), "pick")
    store.save(pick_program(extra=(WaitStep(ms=100),)), "pick")
    store.save(pick_program(extra=(WaitStep(ms=100),), speed=35.0), "pick")

    done = pendant("history", "pick", "--programs", str(tmp_path / "programs"))
    assert done.returncode == 0, done.stderr
    rows = done.stdout.splitlines()
    assert len(rows) == 3 and all("browser #3 (10.0.0.9)" in row for row in rows)
    assert rows[0].endswith("Save pick: step 1 (Move J to P1 @ 35%): speed 20 -> 35 %")
    assert rows[1].endswith("Save pick: step 6 (Wait 100 ms) added")
    assert rows[2].endswith("Save pick: new program, 4 steps, 3 waypoints")
    by_path = pendant("history", str(tmp_path / "programs" / "pick.json"), "--limit", "1")
    assert by_path.stdout.splitlines() == rows[:1]

    oldest = rows[2].split()[0]
    file = tmp_path / "programs" / "pick.json"
    diff = pendant("diff", f"{file}@{oldest}", f"{file}@~0")
    assert diff.stdout.splitlines() == [
        "step 1 (Move J to P1 @ 35%): speed 20 -> 35 %",
        "step 6 (Wait 100 ms) added",
    ]


def test_the_command_line_refuses_bad_input_clearly(tmp_path: Path) -> None:
    ProgramStore(tmp_path).save(pick_program(), "A")
    (tmp_path / "broken.json").write_text('{"schema_version": 2, "steps": [')

    missing = pendant("diff", str(tmp_path / "A.json"), str(tmp_path / "nope.json"))
    assert missing.returncode == EXIT_REFUSED and "nope.json cannot be read" in missing.stderr
    broken = pendant("diff", str(tmp_path / "A.json"), str(tmp_path / "broken.json"))
    assert broken.returncode == EXIT_REFUSED and "is not a JSON document" in broken.stderr
    no_history = pendant("history", "A", "--programs", str(tmp_path))
    assert no_history.returncode == EXIT_REFUSED and "no versions in the history yet" in no_history.stderr
    too_far = pendant("diff", f"{tmp_path / 'A.json'}@~3", str(tmp_path / "A.json"))
    assert too_far.returncode == EXIT_REFUSED and "there is no ~3" in too_far.stderr
    assert "Traceback" not in missing.stderr + broken.stderr + no_history.stderr + too_far.stderr


def test_a_loop_nested_change_is_numbered_as_the_step_list_numbers_it(tmp_path: Path) -> None:
    old = pick_program()
    loop = LoopStep(times=3, body=(WaitStep(ms=500), MoveStep(waypoint="P2")))
    new = old.model_copy(update={"steps": (*old.steps[:3], loop)})
    ProgramStore(tmp_path).save(old, "A")
    ProgramStore(tmp_path).save(new, "B")
    done = pendant("diff", str(tmp_path / "A.json"), str(tmp_path / "B.json"))
    assert done.stdout.splitlines() == ["step 6 (Move J to P2 @ 20%) added"]
