"""Teaching headless: record -> edit -> save -> restart -> load -> run, and the edits an operator makes."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from pendant.controller import MotionType, SignalLevel
from pendant.program import (
    Change,
    EditError,
    GripperAction,
    GripperStep,
    MoveStep,
    OutputStep,
    ProgramFileError,
    ProgramRunner,
    ProgramWorkspace,
    RunState,
    WaitStep,
)
from pendant.program.limits import WAYPOINT_NAME_MAX
from pendant.sim import FakeClock, SimController
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, POSE_C_DEG, settle, teach
from tests.support.waiting import SAFETY_NET_S

ANGLE_TOL_DEG = 1e-6


def test_teach_save_restart_load_and_run_a_pick_and_place(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    changes: list[Change] = []
    workspace.on_change(changes.append)

    # Teach: jog (here: move the simulator) to each place and press Record.
    for pose in (POSE_A_DEG, POSE_B_DEG, POSE_C_DEG):
        teach(sim, clock, pose, "ignored")
        workspace.record_from(sim)
    assert workspace.program.waypoint_names() == ["P1", "P2", "P3"]
    assert Change.PROGRAM in changes

    # Edit: name the places, grip after the approach, go down in a straight line, drop a step, reorder.
    workspace.rename(0, "approach")
    workspace.rename(1, "pick")
    workspace.set_motion(1, MotionType.LINEAR, 30.0)
    grip = workspace.insert_step(GripperStep(action=GripperAction.CLOSE, timeout_ms=200), after=1)
    workspace.insert_step(OutputStep(port=1, level=SignalLevel.HIGH), after=grip)
    workspace.insert_step(WaitStep(ms=50))
    workspace.delete_step(len(workspace.program.steps) - 1)
    workspace.move_step(4, -1)  # P3 before the output
    assert [type(s).__name__ for s in workspace.program.steps] == [
        "MoveStep",
        "MoveStep",
        "GripperStep",
        "MoveStep",
        "OutputStep",
    ]
    teach(sim, clock, POSE_C_DEG, "ignored")
    workspace.reteach_from(sim, 3)

    assert workspace.save_as("pick and place") == "pick and place"
    assert not workspace.dirty

    # Restart the pendant (a new workspace on the same folder) and load the program back.
    sim.reset()
    restarted = make_workspace()
    assert restarted.saved_programs() == ["pick and place"]
    restarted.new()
    assert not restarted.program.steps
    restarted.load("pick and place")
    assert restarted.program == workspace.program

    result = restarted.runner.run(restarted.program, loops=2)

    assert result.state is RunState.FINISHED
    final = restarted.program.steps[3]
    assert isinstance(final, MoveStep)
    taught = restarted.program.waypoint(final.waypoint)
    np.testing.assert_allclose(sim.get_pose().angles, taught.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.HIGH
    assert sim.gripper_opening() == 0.0


def test_record_inserts_after_the_selected_step_with_a_fresh_name(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.record_from(sim)
    workspace.rename(1, "P7")
    index = workspace.record_from(sim, after=0)
    assert index == 1
    assert workspace.program.waypoint_names() == ["P1", "P8", "P7"]
    copy = workspace.duplicate_step(0)
    assert workspace.program.waypoint_names()[copy] == "P1 copy"


def test_edits_that_make_no_sense_are_refused_and_change_nothing(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.record_from(sim)
    before = workspace.program
    with pytest.raises(EditError, match="already exists"):
        workspace.rename(1, "P1")
    with pytest.raises(EditError, match="needs a name"):
        workspace.rename(0, "  ")
    with pytest.raises(EditError, match="no step 9"):
        workspace.delete_step(8)
    workspace.insert_step(WaitStep(ms=10))
    with pytest.raises(EditError, match="not a move"):
        workspace.rename(2, "x")
    assert workspace.program.steps[:2] == before.steps


def test_long_names_are_refused_and_duplicates_stay_loadable_after_a_restart(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    with pytest.raises(EditError, match=f"at most {WAYPOINT_NAME_MAX}"):
        workspace.rename(0, "x" * (WAYPOINT_NAME_MAX + 1))
    longest = "y" * WAYPOINT_NAME_MAX
    workspace.rename(0, longest)
    workspace.duplicate_step(0)
    workspace.duplicate_step(0)
    names = workspace.program.waypoint_names()
    assert len(set(names)) == 3 and all(len(n) <= WAYPOINT_NAME_MAX for n in names)
    restarted = make_workspace()  # the autosave reads back whole: nothing recorded is lost
    assert restarted.program.waypoint_names() == names


def test_loading_a_refused_file_keeps_the_program_on_screen_and_the_file(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace], tmp_path: Path
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.save_as("good")
    newer = {"schema_version": 99, "name": "future", "steps": []}
    path = tmp_path / "programs" / "future.json"
    path.write_text(json.dumps(newer))
    before = workspace.program

    with pytest.raises(ProgramFileError, match="newer pendant"):
        workspace.load("future")
    with pytest.raises(ProgramFileError, match="not a JSON document"):
        workspace.upload("evil.json", b"\x00\x01")

    assert workspace.program == before and workspace.file_name == "good"
    assert json.loads(path.read_text()) == newer


def test_save_as_does_not_overwrite_another_program(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.save_as("first")
    workspace.new()
    workspace.insert_step(WaitStep(ms=5))
    with pytest.raises(ProgramFileError, match="already exists"):
        workspace.save_as("first")
    with pytest.raises(ProgramFileError, match="Save as"):
        workspace.save()
    assert workspace.store.load("first").waypoint_names() == ["P1"]


def test_upload_and_download_round_trip(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.save_as("cell 4")
    filename, data = workspace.download()
    assert filename == "cell 4.json"
    workspace.new()
    workspace.upload("../../etc/cell 4 copy.json", data)
    # The program keeps the name it carries (the browser may have renamed the file on download).
    assert workspace.program.name == "cell 4" and workspace.file_name is None and workspace.dirty
    assert workspace.program.steps == workspace.store.load("cell 4").steps
    nameless = json.loads(data)
    del nameless["name"]
    workspace.upload("../../etc/cell 4 copy.json", json.dumps(nameless).encode())
    assert workspace.program.name == "cell 4 copy"  # none inside: the file's name, without its folders


def test_unsaved_edits_come_back_after_a_restart(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.record_from(sim)
    workspace.save_as("job")
    workspace.insert_step(WaitStep(ms=100))  # not saved: only in the autosave
    restarted = make_workspace()
    assert restarted.file_name == "job" and restarted.dirty
    assert len(restarted.program.steps) == 2


def test_runs_in_the_background_and_reports_progress(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    teach(sim, clock, POSE_A_DEG, "ignored")
    workspace.record_from(sim)
    sim.reset()
    seen: list[Change] = []
    workspace.on_change(seen.append)
    workspace.start_run(loops=1)
    assert workspace.runner.join(timeout=SAFETY_NET_S)
    settle(sim, clock)
    assert workspace.progress.state is RunState.FINISHED
    assert Change.RUN in seen


def test_an_edit_that_cannot_be_autosaved_is_refused_whole(
    sim: SimController, runner: ProgramRunner, tmp_path: Path
) -> None:
    from pendant.program import ProgramStore, ProgramWorkspace

    blocked = tmp_path / "not-a-folder"
    blocked.write_text("a file where the programs folder should be")
    workspace = ProgramWorkspace(ProgramStore(blocked), runner)
    with pytest.raises(OSError):
        workspace.record_from(sim)
    assert workspace.program.steps == ()
