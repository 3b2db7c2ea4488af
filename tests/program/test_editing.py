"""Editing that loses nothing: reusable waypoints (re-teach and rename reach every use), nesting by line,
undo/redo of every edit (New and Load too), version-1 files migrated, files without float noise."""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path

import pytest

from pendant.controller import MotionType, Pose
from pendant.program import (
    EditError,
    GripperAction,
    GripperStep,
    IfStep,
    LoopStep,
    MoveStep,
    Offset,
    PalletStep,
    ProgramStore,
    ProgramWorkspace,
    WaitStep,
    Waypoint,
    compile_program,
)
from pendant.program.plan import MoveGroup
from pendant.sim import FakeClock, SimController
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, POSE_C_DEG, teach


def test_many_moves_to_one_waypoint_follow_its_reteach_and_its_rename(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    teach(sim, clock, POSE_A_DEG, "ignored")
    workspace.record_from(sim)  # line 0: Move to P1
    workspace.insert_step(GripperStep(action=GripperAction.CLOSE))
    workspace.insert_step(MoveStep(waypoint="P1", motion=MotionType.LINEAR, offset=Offset(z=50.0)))
    workspace.insert_step(MoveStep(waypoint="P1"))  # back to the same place
    assert workspace.program.uses_of("P1") == 3 and workspace.program.waypoint_names() == ["P1"]

    teach(sim, clock, POSE_B_DEG, "ignored")
    workspace.reteach_from(sim, 3)  # re-teach through any of its moves
    targets = [
        t for node in compile_program(workspace.program) if isinstance(node, MoveGroup) for t in node.targets
    ]
    assert targets[0].pose == targets[-1].pose == sim.get_pose()
    assert targets[1].position is not None
    assert targets[1].position.point.z == pytest.approx(sim.get_position().point.z + 0.05)

    workspace.rename(0, "pick")
    assert [s.waypoint for s in workspace.program.steps if isinstance(s, MoveStep)] == ["pick"] * 3
    with pytest.raises(EditError, match="used by 3 step"):
        workspace.delete_waypoint("pick")


def test_a_pallet_keeps_its_corners_through_a_rename(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    for pose in (POSE_A_DEG, POSE_B_DEG, POSE_C_DEG):
        teach(sim, clock, pose, "ignored")
        workspace.add_waypoint(sim.get_pose(), sim.get_position())
    workspace.insert_step(PalletStep(corners=("P1", "P2", "P3"), rows=3, columns=4))
    workspace.rename_waypoint("P2", "row end")
    pallet = workspace.program.steps[0]
    assert isinstance(pallet, PalletStep) and pallet.corners == ("P1", "row end", "P3")


def test_steps_nest_and_the_lines_number_the_tree(
    sim: SimController, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    workspace.insert_step(LoopStep(times=2))  # line 0
    workspace.insert_step(WaitStep(ms=10))  # line 1
    workspace.insert_step(IfStep())  # line 2
    assert workspace.indent(1) == 1  # into the loop
    assert [(line.depth, type(line.step).__name__) for line in workspace.lines()] == [
        (0, "LoopStep"),
        (1, "WaitStep"),
        (0, "IfStep"),
    ]
    workspace.insert_into(2, GripperStep(action=GripperAction.OPEN), branch="otherwise")
    workspace.insert_into(2, GripperStep(action=GripperAction.CLOSE))
    assert [(line.branch, type(line.step).__name__) for line in workspace.lines()][3:] == [
        ("then", "GripperStep"),
        ("otherwise", "GripperStep"),
    ]
    workspace.replace_step(2, IfStep(port=3))  # the form changes the condition: what it holds stays
    branch = workspace.program.steps[1]
    assert isinstance(branch, IfStep) and branch.port == 3 and len(branch.then) == len(branch.otherwise) == 1
    assert workspace.outdent(1) == 1  # back out, right after the loop
    assert [line.depth for line in workspace.lines()] == [0, 0, 0, 1, 1]
    with pytest.raises(EditError, match="not inside"):
        workspace.outdent(0)
    with pytest.raises(EditError, match="step above is none"):
        workspace.indent(0)


def test_undo_and_redo_every_edit_including_new_and_load(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace]
) -> None:
    workspace = make_workspace()
    history = [workspace.program]
    workspace.record_from(sim)
    history.append(workspace.program)
    workspace.insert_step(WaitStep(ms=10))
    history.append(workspace.program)
    workspace.rename(0, "home")
    workspace.save_as("job")  # the saved program is what undo brings back
    history.append(workspace.program)
    workspace.new()  # replaces the program on screen
    history.append(workspace.program)
    assert not workspace.program.steps

    workspace.undo()  # New taken back: the program and its file come back
    assert workspace.program == history[3] and workspace.file_name == "job" and not workspace.dirty
    for expected in reversed(history[:3]):
        workspace.undo()
        assert workspace.program == expected
    with pytest.raises(EditError, match="Nothing to undo"):
        workspace.undo()
    for expected in history[1:4]:
        workspace.redo()
        assert workspace.program == expected
    assert make_workspace().program == history[3]  # each undo and redo is autosaved like an edit

    workspace.insert_step(WaitStep(ms=20))  # a new edit ends the redo branch
    with pytest.raises(EditError, match="Nothing to redo"):
        workspace.redo()
    workspace.load("job")
    workspace.undo()
    assert isinstance(workspace.program.steps[-1], WaitStep) and workspace.program.steps[-1].ms == 20


def test_a_version_1_file_is_migrated_and_saved_as_version_2(
    tmp_path: Path, waypoints: dict[str, Waypoint]
) -> None:
    a = waypoints["A"].model_dump(mode="json")
    version_1 = {
        "schema_version": 1,
        "name": "old",
        "steps": [
            {"kind": "move", "waypoint": a, "motion": "JOINT", "speed": 30.0},
            {"kind": "gripper", "action": "close", "timeout_ms": 500},
        ],
    }
    (tmp_path / "old.json").write_text(json.dumps(version_1))
    store = ProgramStore(tmp_path)
    program = store.load("old")
    assert program.schema_version == 2 and program.waypoint_names() == ["A"]
    assert program.steps[0] == MoveStep(waypoint="A", speed=30.0)
    assert program.waypoint("A").pose == Pose.model_validate(a["pose"])
    store.save(program, "old")
    saved = json.loads((tmp_path / "old.json").read_text())
    assert saved["schema_version"] == 2 and saved["steps"][0]["waypoint"] == "A"


def test_saved_files_carry_no_float_noise(
    sim: SimController, clock: FakeClock, make_workspace: Callable[[], ProgramWorkspace], tmp_path: Path
) -> None:
    workspace = make_workspace()
    sim.reset()  # at home: TCP coordinates such as y come out of FK as -9.5e-15, not 0
    workspace.record_from(sim)
    workspace.insert_step(MoveStep(waypoint="P1", motion=MotionType.LINEAR, offset=Offset(x=10.0, rz=90.0)))
    workspace.save_as("clean")
    text = (tmp_path / "programs" / "clean.json").read_text()
    assert not re.search(r"\de-\d", text), re.findall(r"[-\d.]+e-\d+", text)
    _, exported = workspace.export()
    assert not re.search(rb"\de-\d", exported)
