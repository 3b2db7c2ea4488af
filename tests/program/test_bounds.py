"""Programs bounded so that what the pendant accepts it can also run, save, load and export (issue #16,
findings 6 and 9): more than 100 consecutive moves of one type and speed became one run the controller
refused (412 at step 1); an 8,000-step program saved but could not be loaded back; a name containing `\"\"\"`
exported a script that did not compile."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest
from pydantic import ValidationError

from pendant.controller import Pose
from pendant.controller.types import MAX_RUN_WAYPOINTS
from pendant.program import (
    EditError,
    Program,
    ProgramRunner,
    ProgramWorkspace,
    RunState,
    WaitStep,
    Waypoint,
    compile_program,
    export_script,
    program_operations,
)
from pendant.program.files import MAX_FILE_BYTES, dump_program
from pendant.program.limits import MAX_STEPS, PROGRAM_NAME_MAX
from pendant.program.plan import MoveGroup
from pendant.sim import FakeClock, SimController
from tests.support.launchers import running_pendant
from tests.support.programs import Taught, many_moves, move, program_of

LONG_RUN = 2 * MAX_RUN_WAYPOINTS + 50
ANGLE_TOL_DEG = 1e-6
SCRIPT_TIMEOUT_S = 60.0
HOSTILE_NAMES = ['a"""b', "c'''d", "back\\slash", "__OPERATIONS__", "nul\x00x", "new\nline", "tab\tend"]


@pytest.fixture(scope="module")
def api_url() -> Iterator[str]:
    with running_pendant() as url:
        yield url


def sweep(
    template: Waypoint, count: int, degrees_each: float, name: Callable[[int], str] = str
) -> list[Taught]:
    """`count` JOINT moves at one speed, J1 turning `degrees_each` per move from `template`'s pose."""
    start = template.pose.angles
    return [
        move(
            template.model_copy(
                update={"name": name(i), "pose": Pose(angles=[start[0] + degrees_each * (i + 1), *start[1:]])}
            ),
            speed=100.0,
        )
        for i in range(count)
    ]


def test_a_long_stretch_of_moves_becomes_runs_the_controller_accepts(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint]
) -> None:
    moves = sweep(waypoints["A"], LONG_RUN, 0.1)
    program = program_of(*moves)
    groups = [node for node in compile_program(program) if isinstance(node, MoveGroup)]
    assert [len(g.targets) for g in groups] == [MAX_RUN_WAYPOINTS, MAX_RUN_WAYPOINTS, 50]
    runs = [o for o in program_operations(program) if o["op"] == "run_poses"]
    targets = [o["targets"] for o in runs]
    assert [len(t) if isinstance(t, list) else None for t in targets] == [
        MAX_RUN_WAYPOINTS,
        MAX_RUN_WAYPOINTS,
        50,
    ]
    progress = ProgramRunner(sim, sleep=clock.advance, now=clock.now).run(program)
    assert progress.state is RunState.FINISHED, progress.message
    np.testing.assert_allclose(sim.get_pose().angles, moves[-1].waypoint.pose.angles, atol=ANGLE_TOL_DEG)


def exported(program: Program, tmp_path: Path) -> Path:
    """The program's script, written as the page's Export saves it, and compiled."""
    script = tmp_path / "exported.py"
    script.write_bytes(export_script(program).encode())
    compile(script.read_bytes(), str(script), "exec")
    return script


def run_exported(program: Program, tmp_path: Path, api_url: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, str(exported(program, tmp_path)), api_url],
        capture_output=True,
        text=True,
        timeout=SCRIPT_TIMEOUT_S,
        check=False,
    )


def test_the_exported_script_runs_more_than_100_moves_in_runs(
    waypoints: dict[str, Waypoint], tmp_path: Path, api_url: str
) -> None:
    moves = sweep(waypoints["A"], MAX_RUN_WAYPOINTS + 5, 0.02)
    done = run_exported(program_of(*moves), tmp_path, api_url)
    assert done.returncode == 0, done.stderr
    angles = httpx.get(f"{api_url}/pose").json()["angles"]
    np.testing.assert_allclose(angles, moves[-1].waypoint.pose.angles, atol=ANGLE_TOL_DEG)


def test_names_with_quotes_or_control_characters_export_a_script_that_runs(
    waypoints: dict[str, Waypoint], tmp_path: Path, api_url: str
) -> None:
    moves = sweep(waypoints["B"], len(HOSTILE_NAMES), 1.0, name=lambda i: HOSTILE_NAMES[i])
    for name in HOSTILE_NAMES:
        exported(program_of(*moves, WaitStep(ms=1), name=name), tmp_path)
    done = run_exported(program_of(*moves, WaitStep(ms=1), name=HOSTILE_NAMES[0]), tmp_path, api_url)
    assert done.returncode == 0, done.stderr
    angles = httpx.get(f"{api_url}/pose").json()["angles"]
    np.testing.assert_allclose(angles, moves[-1].waypoint.pose.angles, atol=ANGLE_TOL_DEG)


def test_the_largest_program_saves_and_loads_back(
    waypoints: dict[str, Waypoint], make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    largest = many_moves(waypoints["C"], MAX_STEPS, name="n" * PROGRAM_NAME_MAX)
    assert len(dump_program(largest)) <= MAX_FILE_BYTES
    workspace.upload("largest.json", dump_program(largest))
    saved = workspace.save_as("largest")
    make_workspace().load(saved)  # a restarted pendant reads it back
    reloaded = make_workspace()
    reloaded.load(saved)
    as_written = Program.model_validate_json(dump_program(largest))  # files round off float noise
    assert reloaded.program.steps == as_written.steps
    with pytest.raises(EditError, match=f"at most {MAX_STEPS}"):
        reloaded.insert_step(WaitStep(ms=1))
    assert reloaded.program.steps == as_written.steps


def test_a_program_beyond_the_step_limit_cannot_be_made(waypoints: dict[str, Waypoint]) -> None:
    with pytest.raises(ValidationError, match=f"at most {MAX_STEPS}"):
        many_moves(waypoints["C"], 8000)
    with pytest.raises(ValidationError):
        Program(name="n" * (PROGRAM_NAME_MAX + 1))
