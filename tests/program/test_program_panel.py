"""The Program tab headless: a real viser server on loopback, its callbacks fired as a browser would."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
import viser

from pendant.controller import MotionType, SignalLevel
from pendant.eventlog import EventLog
from pendant.program import (
    MoveStep,
    Offset,
    OutputStep,
    PalletStep,
    ProgramRunner,
    ProgramStore,
    ProgramWorkspace,
    RunState,
)
from pendant.sim import FakeClock, SimController
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.banner import Banner
from pendant.ui.page.recovery import Recovery
from pendant.ui.program.panel import NO_SELECTION, ProgramPanel
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.ports import free_port
from tests.support.programs import POSE_A_DEG, POSE_B_DEG, POSE_C_DEG, teach
from tests.support.waiting import SAFETY_NET_S

ANGLE_TOL_DEG = 1e-6
WAIT_S = SAFETY_NET_S


def record(panel: ProgramPanel, client: FakeBrowser) -> None:
    fire(panel.record, client)
    assert panel.pending is not None
    panel.pending.result(timeout=WAIT_S)


def test_record_edit_save_run_download_from_the_tab(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):
        teach(sim, clock, pose, "ignored")
        record(panel, browser)
    sim.reset()
    assert list(panel.select.options) == [NO_SELECTION, "1. Move J to P1 @ 20%", "2. Move J to P2 @ 20%"]
    assert "P2" in panel.steps_view.content
    assert len(panel.scene.markers) == 2

    fire(panel.select, browser, "1. Move J to P1 @ 20%")
    fire(panel.form.speed, browser, 80.0)
    fire(panel.insert_after, browser, True)
    fire(panel.add, browser, "Set DO")  # after the selected step, as asked
    steps = workspace.program.steps
    assert isinstance(steps[0], MoveStep) and steps[0].speed == 80.0
    assert steps[1] == OutputStep(port=1, level=SignalLevel.HIGH)
    fire(panel.waypoints.name, browser, "P1")  # typing alone renames nothing
    fire(panel.select, browser, "3. Move J to P2 @ 20%")
    fire(panel.waypoints.name, browser, "place")
    fire(panel.waypoints.rename, browser)
    assert workspace.program.waypoint_names() == ["P1", "place"]

    fire(panel.file_section.file_name, browser, "cell 4")
    fire(panel.file_section.files, browser, "Save as")
    assert (tmp_path / "programs" / "cell 4.json").is_file()
    assert browser.notifications[-1].startswith("Saved: ")
    assert "`cell 4.json`" in panel.title.content

    fire(panel.run, browser)
    assert workspace.runner.join(timeout=WAIT_S)
    assert workspace.progress.state is RunState.FINISHED
    assert panel.progress.value == 100.0 and panel.run_status.content == "Finished"
    np.testing.assert_allclose(sim.get_pose().angles, POSE_B_DEG, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.HIGH

    fire(panel.file_section.download, browser)
    name, content = browser.downloads[-1]
    assert name == "cell 4.json" and json.loads(content)["steps"][2]["waypoint"] == "place"
    fire(panel.file_section.export, browser)
    assert browser.downloads[-1][0] == "cell_4.py"


def test_a_refused_upload_is_explained_and_changes_nothing(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    record(panel, browser)
    before = workspace.program
    future = viser.UploadedFile(name="future.json", content=b'{"schema_version": 7}')
    fire(panel.file_section.upload, browser, future)
    assert workspace.program == before
    assert browser.notifications[-1].startswith("Upload refused: ")
    assert "newer pendant" in browser.notifications[-1]


def test_two_browsers_see_the_same_program(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController
) -> None:
    panel, workspace = setup
    elsewhere = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)  # its own scene
    other = ProgramPanel(elsewhere, workspace, CommandRunner(sim))
    try:
        record(panel, FakeBrowser(OPERATOR))
        assert list(other.select.options) == [NO_SELECTION, "1. Move J to P1 @ 20%"]
    finally:
        other.close()
        elsewhere.stop()


def test_a_reloaded_page_selects_nothing_and_record_appends(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):
        teach(sim, clock, pose, "ignored")
        record(panel, browser)
    fire(panel.select, browser, "1. Move J to P1 @ 20%")
    panel.close()  # the operator reloads: a new page, its own panel (in a scene of its own)
    elsewhere = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    reloaded = ProgramPanel(elsewhere, workspace, CommandRunner(sim), arm=sim.arm)
    try:
        assert reloaded.selected is None and reloaded.select.value == NO_SELECTION
        ghost = reloaded.waypoints.ghost
        assert ghost is not None and not ghost.show_visual  # nothing selected, nothing previewed
        teach(sim, clock, POSE_C_DEG, "ignored")
        record(reloaded, browser)
        assert [s.waypoint for s in workspace.program.steps if isinstance(s, MoveStep)] == ["P1", "P2", "P3"]
        assert len(workspace.program.steps) == 3
        fire(reloaded.select, browser, "1. Move J to P1 @ 20%")
        assert ghost.show_visual  # a move selected: its waypoint previewed
        record(reloaded, browser)  # a selection alone still appends
        assert workspace.program.steps[-1].waypoint == "P4"
        fire(reloaded.select, browser, "1. Move J to P1 @ 20%")
        fire(reloaded.insert_after, browser, True)  # the visible toggle: after the selected step
        record(reloaded, browser)
        assert [s.waypoint for s in workspace.program.steps] == ["P1", "P5", "P2", "P3", "P4"]
        assert reloaded.select.value == "2. Move J to P5 @ 20%"
    finally:
        reloaded.close()
        elsewhere.stop()


def test_a_corrupt_autosave_is_reported_on_the_tab_and_kept(
    server: viser.ViserServer, sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    folder = tmp_path / "programs"
    folder.mkdir()
    (folder / ".autosave.json").write_text("{ half a program")  # the pendant was killed mid-write by hand
    workspace = ProgramWorkspace(ProgramStore(folder), ProgramRunner(sim, sleep=clock.advance, now=clock.now))
    runner = CommandRunner(sim)
    panel = ProgramPanel(server, workspace, runner, arm=sim.arm)
    try:
        assert workspace.program.steps == ()
        assert "could not be restored" in panel.file_section.status.content
        kept = list(folder.glob(".autosave.refused.*.json"))
        assert len(kept) == 1 and kept[0].read_text() == "{ half a program"
    finally:
        panel.close()
        runner.shutdown()


def test_nothing_is_lost_without_a_question_and_undo_brings_edits_back(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, tmp_path: Path
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    files = panel.file_section
    for _ in range(3):
        record(panel, browser)
    fire(panel.select, browser, "2. Move J to P2 @ 20%")
    # "4\." is no Markdown list item: the numbers stay 1, 2, 3 around the bold (selected) line.
    assert re.findall(r"(\d+)\\\.", panel.steps_view.content) == ["1", "2", "3"]
    assert "**● 2\\." in panel.steps_view.content
    assert "Delete step" in panel.order.options and "Delete file" in files.files.options

    before = workspace.program
    fire(files.files, browser, "New")  # unsaved work: it asks first
    assert workspace.program == before and files.question.visible and files.confirm.visible
    assert "Discard the unsaved changes" in files.question.content
    fire(files.confirm, browser, "Cancel")
    assert workspace.program == before and not files.question.visible
    fire(files.files, browser, "New")
    fire(files.confirm, browser, "Yes")
    assert workspace.program.steps == ()
    fire(panel.history, browser, "Undo")  # the discarded program comes back
    assert workspace.program == before

    fire(files.file_name, browser, "keep me")
    fire(files.files, browser, "Save as")
    fire(files.saved, browser, "keep me")
    fire(files.files, browser, "Delete file")  # a file: always asked
    assert (tmp_path / "programs" / "keep me.json").is_file()
    assert "Delete the file keep me.json?" in files.question.content
    fire(files.confirm, browser, "Yes")
    assert not (tmp_path / "programs" / "keep me.json").exists()

    fire(panel.select, browser, "2. Move J to P2 @ 20%")
    fire(panel.order, browser, "Delete step")
    assert workspace.program.uses_of("P2") == 0
    fire(panel.history, browser, "Undo")
    assert workspace.program.uses_of("P2") == 1
    fire(panel.history, browser, "Redo")
    assert workspace.program.uses_of("P2") == 0


def test_run_from_the_selected_step_and_retry_a_failed_one_from_the_banner(
    setup: tuple[ProgramPanel, ProgramWorkspace],
    server: viser.ViserServer,
    sim: SimController,
    clock: FakeClock,
) -> None:
    panel, workspace = setup
    recovery = Recovery(EventLog(), sim.arm, simulator=True)
    banner = Banner(server, recovery, panel.commands, workspace, sim=sim)

    def read() -> list[str]:  # the page's refresh: the banner reads the controller and the run
        snapshot = Snapshot(taken_at=clock.now(), motion_status=sim.get_motion_status(), online=True)
        recovery.update(snapshot, CellState(), workspace.progress, can_resume=workspace.runner.can_resume)
        banner.show()
        panel.run_section.redraw()
        return [b.label for b in banner.buttons if b.visible]

    browser = FakeBrowser(OPERATOR)
    teach(sim, clock, POSE_A_DEG, "ignored")
    record(panel, browser)
    fire(panel.add, browser, "Wait DI")  # DI1 HIGH, 5 s: nobody sets it, so it fails
    fire(panel.add, browser, "Set DO")
    teach(sim, clock, POSE_B_DEG, "ignored")
    record(panel, browser)
    sim.reset()
    fire(panel.select, browser, "2. Wait DI1 HIGH (timeout 5000 ms)")
    fire(panel.run_section.run_from, browser)
    assert workspace.runner.join(timeout=WAIT_S)
    progress = workspace.progress
    assert progress.state is RunState.FAILED and progress.failed_step == 1
    assert sim.get_pose().angles == pytest.approx([0.0, -90.0, 90.0, -90.0, -90.0, 0.0])  # step 1 skipped
    assert read() == ["Retry step 2", "Skip step 2", "Stop program"] and "✖ 2\\." in panel.steps_view.content
    # The banner says why; the Program tab has no Retry of its own and its run line points to the banner.
    assert banner.view is not None and "failed" in banner.view.detail
    assert "Retry" not in panel.run_status.content and progress.message not in panel.run_status.content
    assert panel.run_status.content.startswith("**Stopped at step 2**")

    sim.set_input(1, SignalLevel.HIGH)
    fire(banner.buttons[0], browser)
    assert workspace.runner.join(timeout=WAIT_S)
    assert workspace.progress.state is RunState.FINISHED
    assert sim.get_output(1) is SignalLevel.HIGH
    np.testing.assert_allclose(sim.get_pose().angles, POSE_B_DEG, atol=ANGLE_TOL_DEG)
    assert read() == [] and panel.run_status.content == "Finished"


def test_the_3d_view_draws_relative_targets_and_the_pallet_grid(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock
) -> None:
    panel, workspace = setup
    for pose in (POSE_A_DEG, POSE_B_DEG, POSE_C_DEG):
        teach(sim, clock, pose, "ignored")
        workspace.add_waypoint(sim.get_pose(), sim.get_position())
    workspace.insert_step(MoveStep(waypoint="P1", motion=MotionType.LINEAR, offset=Offset(z=50.0)))
    workspace.insert_step(PalletStep(corners=("P1", "P2", "P3"), rows=3, columns=4, approach_mm=30.0))
    cells = [node for node in panel.scene.nodes if node.name == "/program/pallet_cells"]
    assert len(cells) == 1 and isinstance(cells[0], viser.PointCloudHandle)
    assert cells[0].points.shape == (12, 3)
    p1 = workspace.program.waypoint("P1").position.point
    marker_points = [np.asarray(marker.position) for marker, _ in panel.scene.markers]
    above_p1 = np.array([p1.x, p1.y, p1.z + 0.05])
    assert min(float(np.linalg.norm(p - above_p1)) for p in marker_points) < 1e-4  # the relative target
    assert any(abs(float(p[2]) - (p1.z + 0.03)) < 1e-4 for p in marker_points)  # above the first cell


def test_save_of_an_unnamed_program_asks_for_its_name_then_saves(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    panel, workspace = setup
    files, browser, folder = panel.file_section, FakeBrowser(OPERATOR), tmp_path / "programs"
    teach(sim, clock, POSE_A_DEG, "ignored")
    record(panel, browser)
    assert workspace.file_name is None

    fire(files.files, browser, "Save")  # no name yet: asked for one in the name box, not refused
    assert files.name_prompt.visible and "Name this program" in files.name_prompt.content
    assert 'data-pendant-focus="Save as name"' in files.name_prompt.content  # the page focuses that box
    assert browser.notifications == [] and list(folder.glob("[!.]*.json")) == []  # .autosave.json aside
    asked = files.name_prompt.content
    fire(files.files, browser, "Save")  # asked again: a new question, so the box is focused again
    assert files.name_prompt.content != asked

    fire(files.file_name, browser, "first job")
    fire(files.files, browser, "Save")
    assert json.loads((folder / "first job.json").read_text())["name"] == "first job"
    assert workspace.file_name == "first job" and not workspace.dirty
    assert browser.notifications[-1].startswith("Saved: ") and not files.name_prompt.visible

    fire(files.files, browser, "New")
    record(panel, browser)  # the box still says "first job": Save does not write over that file
    fire(files.files, browser, "Save")
    assert "'first job' already exists" in files.name_prompt.content
    assert [s["kind"] for s in json.loads((folder / "first job.json").read_text())["steps"]] == ["move"]
    fire(files.file_name, browser, "../escape")  # a name that would leave the folder: asked again
    fire(files.files, browser, "Save")
    assert "not a usable program name" in files.name_prompt.content
    assert sorted(p.name for p in tmp_path.rglob("[!.]*.json")) == ["first job.json"]
    fire(files.file_name, browser, "second job")
    fire(files.files, browser, "Save")
    assert (folder / "second job.json").is_file() and workspace.file_name == "second job"


def test_reteach_keeps_the_waypoint_chosen_and_says_how_far_it_moved(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):
        teach(sim, clock, pose, "ignored")
        record(panel, browser)
    fire(panel.select, browser, "1. Move J to P1 @ 20%")  # a step to P1 selected, P2 chosen to re-teach
    fire(panel.waypoints.chooser, browser, "P2")
    before = workspace.program.waypoint("P2").position.point
    teach(sim, clock, POSE_C_DEG, "ignored")
    fire(panel.waypoints.reteach, browser)
    assert panel.pending is not None
    panel.pending.result(timeout=WAIT_S)
    after = sim.get_position().point
    moved_mm = 1000.0 * float(np.linalg.norm([after.x - before.x, after.y - before.y, after.z - before.z]))
    assert moved_mm > 1.0
    assert panel.waypoints.chooser.value == "P2"  # not the selected step's P1
    assert browser.notifications[-1] == f"P2 re-taught: moved {moved_mm:.0f} mm"


def test_moves_back_to_a_waypoint_share_its_name_label_and_near_ones_stack_never_drawn_over_each_other(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    for pose in (POSE_A_DEG, POSE_B_DEG):  # a pick-and-place: P1, P2, then back to P1 and P2
        teach(sim, clock, pose, "ignored")
        record(panel, browser)
    workspace.insert_step(MoveStep(waypoint="P1"))
    workspace.insert_step(MoveStep(waypoint="P2"))
    near = tuple(a + d for a, d in zip(POSE_B_DEG, (0.5, 0, 0, 0, 0, 0), strict=True))  # a few mm from P2
    teach(sim, clock, near, "ignored")
    record(panel, browser)
    assert len(panel.scene.markers) == 5  # every move keeps its marker
    assert panel.scene.labels == ["1, 3. P1", "2, 4. P2\n5. P3"]  # one label per place: none on another
