"""The Program tab's Check and the Run gate, headless (a real viser server, callbacks fired as a browser's),
on a "real" arm: the pendant drives a `pendant --no-ui` process through a RemoteController."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import viser

from pendant.controller.types import MotionParams, MotionStatus, Pose
from pendant.kinematics import ArmModel
from pendant.planning.report import PreflightReport
from pendant.program import ProgramRunner, ProgramStore, ProgramWorkspace, RunState
from pendant.program.models import LoopStep
from pendant.remote import RemoteController
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.program.check_section import MSG_RUNNING
from pendant.ui.program.panel import ProgramPanel
from tests.support.doubles import FakeBrowser, fire
from tests.support.launchers import running_pendant
from tests.support.ports import free_port
from tests.support.preflight_scene import BOX_NAME, LEFT_DEG, box_in_the_way, swing_program
from tests.support.waiting import SAFETY_NET_S, wait_until

WAIT_S = 30.0
# The swing takes ~12 s at 15 %: 3 s on an arm four times faster, so a starved pass behind the timed one
# (CI's ran 16 min) still sees it end well within the wait.
ARM_TIME_SCALE = "4"
RUN_WAIT_S = 60.0
PASSES = 100  # 300 moves: seconds of checking on the twin


@pytest.fixture(scope="module")
def arm_url() -> Iterator[str]:
    with running_pendant("--time-scale", ARM_TIME_SCALE) as url:
        yield url


@pytest.fixture
def checked(
    arm_url: str, tmp_path: Path
) -> Iterator[tuple[ProgramPanel, ProgramWorkspace, RemoteController]]:
    arm = RemoteController(arm_url)
    arm.remove_obstacles()
    arm.set_pose(Pose(angles=list(LEFT_DEG)), MotionParams(speed=100.0))
    wait_until(lambda: arm.get_motion_status() is MotionStatus.IDLE, timeout_s=SAFETY_NET_S)
    arm.add_obstacle(box_in_the_way())
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    commands = CommandRunner(arm)
    workspace = ProgramWorkspace(ProgramStore(tmp_path / "programs"), ProgramRunner(arm))
    workspace.open_uploaded(swing_program())
    panel = ProgramPanel(server, workspace, commands, arm=ArmModel.load("pulse75"))
    yield panel, workspace, arm
    panel.close()
    commands.shutdown()
    server.stop()


def check(panel: ProgramPanel, browser: FakeBrowser) -> Any:
    fire(panel.check_section.check, browser)
    assert panel.pending is not None
    return panel.pending.result(timeout=WAIT_S)


def test_run_waits_for_a_passing_check_and_check_marks_the_failing_step(
    checked: tuple[ProgramPanel, ProgramWorkspace, RemoteController],
) -> None:
    panel, workspace, arm = checked
    browser = FakeBrowser(1)
    section = panel.check_section
    assert section.shared.gate.required and section.override.visible  # a real arm: the gate is on

    fire(panel.run, browser)
    assert browser.notifications[-1].startswith("Run refused: Check the program first")
    assert workspace.progress.state is RunState.IDLE

    report = check(panel, browser)
    assert report is not None and not report.ok
    rows = panel.steps_view.content.split("  \n")
    assert f"✘ the gripper would hit '{BOX_NAME}'" in rows[2]
    assert "✔" in rows[0] and "○ not checked" in rows[3] and "✘ not checked" not in rows[3]
    assert section.summary.content.startswith("**✘ Step 3 (Move J to right")
    assert {node.name for node in section.nodes} == {"/program_check/swept", "/program_check/failure"}
    assert not section.playback.disabled and section.playback.max == pytest.approx(
        report.cycle_time_s, abs=0.01
    )

    fire(panel.run, browser)
    assert "The last pre-flight of this program failed" in browser.notifications[-1]
    assert workspace.progress.state is RunState.IDLE and arm.get_motion_status() is MotionStatus.IDLE

    arm.remove_obstacles()  # the cell changed: check again, and this time it passes
    report = check(panel, browser)
    assert report.ok and "✘" not in panel.steps_view.content
    fire(panel.run, browser)
    wait_until(
        lambda: workspace.progress.state is RunState.FINISHED,
        timeout_s=RUN_WAIT_S,
        what=lambda: f"the run's end ({workspace.progress}; said: {browser.notifications[-3:]})",
    )


def test_playback_moves_the_ghost_and_the_step_list_follows(
    checked: tuple[ProgramPanel, ProgramWorkspace, RemoteController],
) -> None:
    panel, _, arm = checked
    arm.remove_obstacles()
    browser = FakeBrowser(1)
    report = check(panel, browser)
    middle_of_step_3 = next(t for t, line, _ in report.timeline if line == 2) + 0.5
    fire(panel.check_section.playback, browser, middle_of_step_3)
    assert panel.selected == 2
    ghost = panel.waypoints.ghost
    assert ghost is not None and ghost.show_visual


def test_a_second_check_while_one_runs_is_refused_and_the_first_one_reports(
    checked: tuple[ProgramPanel, ProgramWorkspace, RemoteController],
) -> None:
    """One check at a time (issue #32): a click on Check while one runs is refused with a message, not queued
    as one more pre-flight of up to 30 s ahead of the operator's next commands."""
    panel, workspace, arm = checked
    arm.remove_obstacles()
    swings = LoopStep(times=PASSES, body=swing_program().steps)
    workspace.open_uploaded(swing_program().model_copy(update={"steps": (swings,)}))
    browser = FakeBrowser(1)
    fire(panel.check_section.check, browser)
    first = panel.pending
    fire(panel.check_section.check, browser)
    assert browser.notifications[-1] == f"Check refused: {MSG_RUNNING}"
    assert panel.pending is first  # nothing more was queued
    assert first is not None
    report = first.result(timeout=WAIT_S)
    assert isinstance(report, PreflightReport) and report.ok
    assert check(panel, browser).ok  # once it has ended, Check runs again
