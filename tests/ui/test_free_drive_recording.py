"""Free drive in the page (simulator) and path recording, headless: the operator pulls the relaxed arm with
the joint sliders; a recording of that becomes one Path step in the program, within the tolerance."""

from __future__ import annotations

import json
import time
from collections.abc import Callable

import numpy as np

from pendant.program import describe_step
from pendant.program.models import PathStep
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser
from tests.support.obstacles import box
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S
STEPS = 45


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.01)


def pose(sim: SimController) -> np.ndarray:
    return np.radians(sim.get_pose().angles)


def pull_to(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController, q: np.ndarray, who: FakeBrowser
) -> None:
    ui.target_panel.set_joint_target(q, who.handle)
    wait_for(lambda: np.allclose(pose(sim), q, atol=1e-9), "the arm to follow the hand")
    pendant_ui.refresh()


def test_in_free_drive_the_sliders_move_the_arm_but_not_into_an_obstacle(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    operator = FakeBrowser(OPERATOR)
    home = pose(sim)
    turned = home.copy()
    turned[0] += np.radians(20.0)
    ui.target_panel.set_joint_target(turned, operator.handle)  # not in free drive: only the ghost moves
    time.sleep(0.2)
    np.testing.assert_allclose(pose(sim), home)

    ui.robot_safety.set_free_drive(True, operator.handle).result(timeout=WAIT_S)
    pendant_ui.refresh_cell()
    pull_to(pendant_ui, ui, sim, turned, operator)
    assert ui.target_panel.ghost_shown is None  # no ghost: the arm is where the hand put it

    further = turned.copy()
    further[0] += np.radians(30.0)
    sim.add_obstacle(box("in the way", tuple(sim.arm.fk(further)[:3, 3])))
    pendant_ui.refresh_cell()
    check = ui.target_panel.set_joint_target(further, operator.handle)
    assert not check.ok and "Collision detected" in (check.reason or "")
    time.sleep(0.2)
    np.testing.assert_allclose(pose(sim), turned)  # the arm stays short of the obstacle


def test_a_free_driven_path_is_recorded_simplified_into_the_program_and_downloadable(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    operator = FakeBrowser(OPERATOR)
    ui.robot_safety.set_free_drive(True, operator.handle).result(timeout=WAIT_S)
    pendant_ui.refresh_cell()
    home = pose(sim)
    assert ui.record.begin(operator.handle)
    pendant_ui.refresh()
    for i in range(1, STEPS + 1):  # a curve: J1 sweeps while J2 and J3 bend and straighten
        s = i / STEPS
        q = home + np.radians([40.0 * s, 15.0 * np.sin(np.pi * s), -20.0 * np.sin(np.pi * s), 0.0, 0.0, 0.0])
        pull_to(pendant_ui, ui, sim, q, operator)
    line = ui.record.end(operator.handle)

    steps = pendant_ui.programs.program.steps
    assert line == 0 and len(steps) == 1  # one step, however many waypoints
    path = steps[0]
    assert isinstance(path, PathStep) and 2 < len(path.points) <= 100 and path.name == "path1"
    np.testing.assert_allclose(path.points[0].pose.angles, np.degrees(home), atol=1e-6)
    np.testing.assert_allclose(path.points[-1].pose.angles, np.degrees(pose(sim)), atol=1e-6)
    assert path.points[-1].position == sim.get_position()
    assert (path.tol_mm, path.tol_deg) == (1.0, 1.0)
    assert f"**{len(path.points)} waypoints** within 1 mm / 1°" in ui.record.note.content
    listed = ui.program.steps_view.content
    assert describe_step(path).startswith(f"Path path1: {len(path.points)} waypoints, 1 mm / 1°")
    assert describe_step(path) in listed
    assert pendant_ui.programs.program.waypoints == ()  # its points are its own, not named waypoints

    data = ui.record.send(operator.handle)
    assert data is not None and operator.downloads[-1][1] == data
    folder = pendant_ui.recorder.folder  # kept in the data folder, named by the step
    assert folder is not None and path.recording is not None and path.recording.startswith("path-")
    assert (folder / path.recording).read_bytes() == data
    assert f"kept as `{path.recording}`" in ui.record.note.content
    recording = json.loads(data)
    assert recording["format"] == "pulse-pendant-path-recording" and recording["schema_version"] == 1
    samples = recording["samples"]
    assert len(samples) == STEPS + 1
    assert [s["t"] for s in samples] == sorted(s["t"] for s in samples)
    assert set(samples[0]) == {"t", "joints_deg", "tcp", "outputs", "inputs"}
    assert samples[0]["inputs"] == {"1": "LOW", "2": "LOW", "3": "LOW", "4": "LOW"}
