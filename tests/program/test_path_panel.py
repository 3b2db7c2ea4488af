"""A Path step in the Program tab, headless: one line in the step list, a polyline through its waypoints in
3D (a marker only at its end), its speeds edited in the form, moved and deleted like any step; and a run on a
controller without /run/* saying so under the progress."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import viser
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller import SignalLevel
from pendant.planning.report import PreflightReport
from pendant.program import OutputStep, PathStep, ProgramRunner, ProgramStore, ProgramWorkspace, RunState
from pendant.program.blended import FALLBACK_NOTE
from pendant.remote import RemoteController
from pendant.sim import FakeClock, SimController
from pendant.teach.path_step import path_step
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.program.panel import ProgramPanel
from pendant.ui.program.scene import ROOT
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.path_playback import WithoutRunOperations, hand_drawn_s

WAIT_S = 60.0  # a safety net: the pass may get next to no CPU for seconds (docs/development.md)


def test_a_path_step_is_one_line_drawn_as_a_polyline_and_edited_as_a_whole(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    step = path_step(hand_drawn_s(sim, clock), name="s1")
    workspace.insert_step(OutputStep(port=1, level=SignalLevel.HIGH))
    workspace.insert_step(step)
    count = len(step.points)
    line = f"2. Path s1: {count} waypoints, 1 mm / 1° @ 100 mm/s"
    assert list(panel.select.options)[2] == line  # after "(no step selected)" and line 1

    drawn = {node.name: node for node in panel.scene.nodes}
    polyline = drawn[f"{ROOT}/recorded_paths"]
    dots = drawn[f"{ROOT}/recorded_waypoints"]
    assert isinstance(polyline, viser.LineSegmentsHandle) and isinstance(dots, viser.PointCloudHandle)
    assert polyline.points.shape[1:] == (2, 3) and len(polyline.points) == count - 1
    end = step.points[-1].position.point
    assert np.allclose(dots.points[-1], [end.x, end.y, end.z], atol=1e-6)
    # A marker at its start (where the arm goes first) and one at its end: not one per waypoint.
    assert [step_line for _, step_line in panel.scene.markers] == [1, 1]

    fire(panel.select, browser, line)
    assert panel.form.path_speed.visible and panel.form.speed.visible and not panel.form.goes_to.visible
    fire(panel.form.path_speed, browser, 40.0)
    edited = workspace.program.steps[1]
    assert isinstance(edited, PathStep) and edited.velocity_mm_s == 40.0 and edited.points == step.points
    fire(panel.form.path_speed, browser, 1e9)  # beyond 2 m/s: refused, nothing changed
    assert workspace.program.steps[1] == edited and browser.notifications[-1].startswith(
        "Edit step refused: "
    )

    # Another tolerance simplifies the path again from its kept recording (here: none kept, refused).
    fire(panel.form.path_tol, browser, (2.0, 2.0))
    assert workspace.program.steps[1] == edited and "no kept recording" in browser.notifications[-1]

    fire(panel.order, browser, "Up")
    assert isinstance(workspace.program.steps[0], PathStep)
    fire(panel.select, browser, panel.select.options[1])
    fire(panel.order, browser, "Delete step")
    assert [type(s) for s in workspace.program.steps] == [OutputStep]


def test_another_tolerance_simplifies_the_kept_recording_again(
    setup: tuple[ProgramPanel, ProgramWorkspace], sim: SimController, clock: FakeClock, tmp_path: Path
) -> None:
    panel, workspace = setup
    browser = FakeBrowser(OPERATOR)
    workspace.path_recordings = tmp_path / "recordings"
    recording = hand_drawn_s(sim, clock, folder=workspace.path_recordings)
    step = path_step(recording, name="s1").model_copy(update={"velocity_mm_s": 40.0})
    workspace.insert_step(step)
    fire(panel.select, browser, panel.select.options[1])

    fire(panel.form.path_tol, browser, (4.0, 4.0))

    coarser = workspace.program.steps[0]
    assert isinstance(coarser, PathStep) and (coarser.tol_mm, coarser.tol_deg) == (4.0, 4.0)
    assert len(coarser.points) < len(step.points) and coarser.points[-1] == step.points[-1]
    assert (coarser.name, coarser.velocity_mm_s, coarser.recording) == ("s1", 40.0, recording.file)
    fire(panel.history, browser, "Undo")
    assert workspace.program.steps[0] == step


def test_on_a_controller_without_run_operations_the_tab_says_the_path_played_stop_and_go(
    server: viser.ViserServer,
    sim: SimController,
    clock: FakeClock,
    tmp_path: Path,
) -> None:
    step = path_step(hand_drawn_s(sim, clock), name="s1")
    with TestClient(WithoutRunOperations(create_app(sim))) as http:
        older = RemoteController("http://testserver", client=http)
        workspace = ProgramWorkspace(
            ProgramStore(tmp_path / "programs"), ProgramRunner(older, sleep=clock.advance, now=clock.now)
        )
        commands = CommandRunner(older)
        panel = ProgramPanel(server, workspace, commands, arm=sim.arm)
        try:
            workspace.insert_step(step)
            # A real arm: Run waits for a passing check.
            fire(panel.check_section.check, FakeBrowser(OPERATOR))
            assert panel.pending is not None
            report = panel.pending.result(timeout=WAIT_S)
            assert isinstance(report, PreflightReport) and report.ok
            fire(panel.run, FakeBrowser(OPERATOR))
            assert workspace.runner.join(timeout=WAIT_S)
            assert workspace.progress.state is RunState.FINISHED
            assert panel.run_status.content == f"Finished\n\n{FALLBACK_NOTE}"
        finally:
            # The run ends before the app it talks to: a run still sending when the TestClient closes
            # waits on it for good (CI, 1 Dec: 300 s, then pytest-timeout).
            workspace.runner.request_stop("the test's end")
            workspace.runner.join(timeout=WAIT_S)
            panel.close()
            commands.shutdown()
