"""The Cell tab and the cell in 3D, headless: what the simulator holds is what the page draws and checks."""

from __future__ import annotations

import json
import time
from collections.abc import Callable

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionType, Point, Pose, Position
from pendant.controller.cell_types import (
    BoxObstacle,
    CapsuleObstacle,
    PlaneObstacle,
    SimplifiedCapsuleObstacle,
    ToolShape,
)
from pendant.jog import JogFrame, JogRequest
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.cell.panel import NEW
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, fire
from tests.support.obstacles import box
from tests.support.pages import sent
from tests.support.sim_sampling import home_q
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.02)


def box_x(sim: SimController, name: str) -> float:
    obstacle = sim.get_obstacle(name)
    assert isinstance(obstacle, BoxObstacle)
    return obstacle.centerPosition.point.x


def names(sim: SimController) -> list[str]:
    return [o.name for o in sim.get_obstacles()]


def test_an_obstacle_added_through_the_controller_is_drawn_and_listed(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.add_obstacle(box("script box", (0.4, 0.3, 0.2)))
    pendant_ui.refresh_cell()
    assert pendant_ui.obstacles.shown == {"script box": False}  # drawn, orange (the arm does not touch it)
    assert "script box" in ui.cell.selected.options
    assert "1 obstacle(s)" in ui.cell.note.content

    sim.remove_obstacle("script box")
    pendant_ui.refresh_cell()
    assert pendant_ui.obstacles.shown == {}
    assert "script box" not in ui.cell.selected.options


def test_the_cell_tab_adds_renames_and_deletes_on_the_controller(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    browser = FakeBrowser(OPERATOR)
    fire(ui.cell.kind, browser, "BOX")
    fire(ui.cell.name, browser, "table")
    fire(ui.cell.at, browser, (500.0, 0.0, 50.0))
    fire(ui.cell.rpy, browser, (0.0, 0.0, 30.0))
    fire(ui.cell.size, browser, (300.0, 600.0, 100.0))
    assert ui.cell.apply.disabled  # "(new obstacle)": nothing to update, only Add
    fire(ui.cell.add, browser)
    wait_for(lambda: names(sim) == ["table"], "the box on the controller")
    table = sim.get_obstacle("table")
    assert isinstance(table, BoxObstacle)
    assert (table.sides.x, table.sides.y, table.sides.z) == pytest.approx((0.3, 0.6, 0.1))
    assert table.centerPosition.point.x == pytest.approx(0.5)
    assert np.degrees(table.centerPosition.rotation.yaw) == pytest.approx(30.0)
    pendant_ui.refresh_cell()
    assert ui.cell.selected.value == "table"  # the one just added is the one being edited

    fire(ui.cell.name, browser, "bench")  # rename: same obstacle, new name
    sent(ui.cell.submit(browser.handle)).result(timeout=WAIT_S)
    assert names(sim) == ["bench"]
    pendant_ui.refresh_cell()
    assert ui.cell.selected.value == "bench"

    fire(ui.cell.delete, browser)  # asks first
    assert names(sim) == ["bench"] and "Delete the obstacle 'bench'?" in ui.cell.confirmation.question.content
    fire(ui.cell.confirmation.buttons, browser, "Yes")
    wait_for(lambda: names(sim) == [], "the obstacle deleted")
    assert browser.notifications == []


def test_update_edits_the_selected_obstacle_and_add_never_replaces_one(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    browser = FakeBrowser(OPERATOR)
    for name, x in (("left", 400.0), ("right", 600.0)):
        fire(ui.cell.selected, browser, NEW)
        fire(ui.cell.name, browser, name)
        fire(ui.cell.at, browser, (x, 300.0, 100.0))
        sent(ui.cell.submit(browser.handle, add=True)).result(timeout=WAIT_S)
        pendant_ui.refresh_cell()
    fire(ui.cell.selected, browser, "left")
    fire(ui.cell.at, browser, (450.0, 350.0, 100.0))  # moved, then Update: the same obstacle, moved
    fire(ui.cell.apply, browser)
    wait_for(lambda: box_x(sim, "left") == pytest.approx(0.45), "left moved")
    assert names(sim) == ["left", "right"]

    fire(ui.cell.add, browser)  # the selected one's name: Add would replace it, so it is refused
    fire(ui.cell.name, browser, "right")
    fire(ui.cell.apply, browser)  # renaming onto another obstacle's name would replace that one
    assert browser.notifications == [
        "Obstacle not added: an obstacle is already called 'left': pick another name",
        "Obstacle not renamed: an obstacle is already called 'right': pick another name",
    ]
    assert names(sim) == ["left", "right"]

    fire(ui.cell.clear, browser)  # asks first; Cancel keeps everything
    assert "Delete all 2 obstacles?" in ui.cell.confirmation.question.content
    fire(ui.cell.confirmation.buttons, browser, "Cancel")
    assert names(sim) == ["left", "right"] and not ui.cell.confirmation.question.visible


def test_a_capsule_from_the_form_keeps_its_ends_and_radius(ui: ClientSession, sim: SimController) -> None:
    browser = FakeBrowser(OPERATOR)
    fire(ui.cell.kind, browser, "CAPSULE")
    fire(ui.cell.name, browser, "post")
    fire(ui.cell.at, browser, (400.0, 300.0, 0.0))
    fire(ui.cell.end, browser, (400.0, 300.0, 600.0))
    fire(ui.cell.radius, browser, 40.0)
    sent(ui.cell.submit(browser.handle, add=True)).result(timeout=WAIT_S)
    post = sim.get_obstacle("post")
    assert isinstance(post, CapsuleObstacle)
    assert post.radius == pytest.approx(0.04)
    assert (post.finish.x, post.finish.y, post.finish.z) == pytest.approx((0.4, 0.3, 0.6))


def test_bad_fields_and_viewers_are_refused_and_the_cell_is_unchanged(
    ui: ClientSession, sim: SimController
) -> None:
    operator, viewer = FakeBrowser(OPERATOR), FakeBrowser(VIEWER)
    fire(ui.cell.kind, operator, "BOX")
    fire(ui.cell.name, operator, "flat")
    fire(ui.cell.size, operator, (100.0, 0.0, 100.0))
    assert ui.cell.submit(operator.handle, add=True) is None
    assert operator.notifications == ["Obstacle not added: a box's sides must be longer than 0 mm"]

    fire(ui.cell.size, operator, (100.0, 100.0, 100.0))
    refused = ui.cell.submit(viewer.handle, add=True)
    assert refused is not None and refused.exception(timeout=WAIT_S) is not None
    assert any("refused" in n for n in viewer.notifications)
    assert names(sim) == []


def test_an_obstacle_touching_the_arm_is_taken_shown_red_said_and_logged(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController, clock: FakeClock
) -> None:
    pendant_ui.refresh_cell()  # the page has read the (empty) cell, as it does a few times a second
    browser = FakeBrowser(OPERATOR)
    flange = sim.arm.fk(home_q(sim))[:3, 3]
    fire(ui.cell.kind, browser, "BOX")
    fire(ui.cell.name, browser, "on the arm")
    beside = flange + np.array([-0.07, 0.0, 0.0])  # its +x face 2 cm into the wrist and the gripper
    fire(ui.cell.at, browser, tuple(float(v) for v in beside * 1000.0))
    future = ui.cell.submit(browser.handle, add=True)
    assert future is not None and future.result(timeout=WAIT_S) is not None  # taken, as a controller does
    assert names(sim) == ["on the arm"]
    pendant_ui.refresh_cell()
    assert pendant_ui.obstacles.shown == {"on the arm": True}  # drawn red
    assert "**The arm touches 'on the arm' (link5, link6, gripper_body" in ui.cell.note.content
    assert "not deeper in" in ui.cell.note.content
    logged = [e.message for e in pendant_ui.events.recent() if e.source == "cell"]
    assert logged == [
        "Obstacle 'on the arm' added touching the arm (link5, link6, gripper_body, finger_left, finger_right)"
    ]

    # Backed out (10 cm along +x, away from it), the arm is clear: orange again, no line, logged once.
    here = sim.get_position()
    out = Position(point=Point(x=here.point.x + 0.1, y=here.point.y, z=here.point.z), rotation=here.rotation)
    sim.set_position(out, MotionParams(speed=50.0, motion_type=MotionType.LINEAR, tcp_max_velocity=0.2))
    clock.advance(10.0)
    pendant_ui.refresh()
    pendant_ui.refresh_cell()
    pendant_ui.refresh_cell()
    assert pendant_ui.obstacles.shown == {"on the arm": False}
    assert "touches" not in ui.cell.note.content
    logged = [e.message for e in pendant_ui.events.recent() if e.source == "cell"]
    assert logged[1:] == ["The arm is clear of obstacle 'on the arm'"]


def test_an_obstacle_touching_the_moving_arm_is_refused_with_the_controllers_message(
    ui: ClientSession, sim: SimController
) -> None:
    browser = FakeBrowser(OPERATOR)
    away = sim.get_pose().angles
    away[0] += 30.0
    sim.set_pose(Pose(angles=away), MotionParams(speed=10.0))  # the fake clock holds it in motion
    flange = sim.arm.fk(home_q(sim))[:3, 3] * 1000.0
    fire(ui.cell.kind, browser, "BOX")
    fire(ui.cell.name, browser, "on the arm")
    fire(ui.cell.at, browser, tuple(float(v) for v in flange))
    future = ui.cell.submit(browser.handle, add=True)
    assert future is not None and future.exception(timeout=WAIT_S) is not None
    assert any("Collision detected: the obstacle touches the arm" in n for n in browser.notifications)
    assert names(sim) == []


def test_the_ghost_turns_red_for_a_target_or_a_path_through_an_obstacle(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    q = home_q(sim)
    around = q.copy()
    around[0] += np.radians(90.0)
    panel = ui.target_panel
    assert panel.set_joint_target(around).ok  # an empty cell: fine

    halfway = q.copy()
    halfway[0] += np.radians(45.0)
    sim.add_obstacle(box("in the way", tuple(sim.arm.fk(halfway)[:3, 3])))
    pendant_ui.refresh_cell()  # the cell changed: the target is checked again
    assert not panel.check.ok
    assert panel.check.reason == "Collision detected: the path to the target passes through 'in the way'"
    assert panel.ghost_shown is False  # the red ghost
    assert panel.move_j.disabled and panel.move_l.disabled
    assert panel.obstacles_hit == {"in the way": True}  # drawn red in this browser

    sim.add_obstacle(box("at the target", tuple(sim.arm.fk(around)[:3, 3])))
    pendant_ui.refresh_cell()
    assert panel.check.reason == "Collision detected: the arm would touch 'at the target'"

    sim.remove_obstacles()
    pendant_ui.refresh_cell()
    assert panel.check.ok and panel.ghost_shown is True
    assert panel.obstacles_hit == {}


def test_the_tool_shape_is_drawn_on_the_flange_and_the_ghost_checks_it(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    flange = sim.arm.fk(home_q(sim))
    along = flange[:3, 2]  # the flange's z axis: where the tool points
    sim.add_obstacle(box("below the tool", tuple(flange[:3, 3] + 0.25 * along), side=0.04))
    pendant_ui.refresh_cell()
    lowered = flange.copy()
    lowered[:3, 3] += 0.1 * along
    panel = ui.target_panel
    assert panel.set_flange_target(lowered).ok  # the bare flange stops 13 cm short of the box

    capsule = SimplifiedCapsuleObstacle(
        radius=0.03, begin=Point(x=0.0, y=0.0, z=0.0), finish=Point(x=0.0, y=0.0, z=0.15)
    )
    sim.set_tool_shape(ToolShape(shape=[capsule]))
    pendant_ui.refresh_cell()
    pendant_ui.refresh()
    assert pendant_ui.tool_shape.capsules_shown == 1
    np.testing.assert_allclose(pendant_ui.tool_shape.frame.position, flange[:3, 3], atol=1e-6)
    assert panel.check.reason == "Collision detected: the arm would touch 'below the tool'"


def test_a_cell_file_is_saved_loaded_and_applied(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    folder = ui.cell.files_section.folder  # a fresh one per test (tests/conftest.py)
    browser = FakeBrowser(OPERATOR)
    sim.add_obstacle(box("fixture", (0.4, 0.3, 0.2)))
    fire(ui.cell.file_name, browser, "line 3")
    ui.cell.save_file(browser.handle).result(timeout=WAIT_S)
    saved = json.loads((folder / "line 3.cell.json").read_text())
    assert saved["schema_version"] == 1
    assert [o["name"] for o in saved["obstacles"]] == ["fixture"]
    assert ui.cell.files.value == "line 3"

    sim.remove_obstacles()
    sim.add_obstacle(box("other", (-0.4, 0.3, 0.2)))
    sent(ui.cell.load_file("line 3", browser.handle)).result(timeout=WAIT_S)
    assert names(sim) == ["fixture"]  # exactly the saved cell


def test_a_cell_file_the_controller_refuses_leaves_the_cell_as_it_was(
    ui: ClientSession, sim: SimController
) -> None:
    folder = ui.cell.files_section.folder  # a fresh one per test (tests/conftest.py)
    browser = FakeBrowser(OPERATOR)
    on_a_line = PlaneObstacle(
        obstacleType="PLANE",
        name="wall",
        points=[Point(x=0.0, y=0.0, z=0.0), Point(x=0.1, y=0.0, z=0.0), Point(x=0.2, y=0.0, z=0.0)],
    )
    bad = {"schema_version": 1, "obstacles": [json.loads(on_a_line.model_dump_json())]}
    (folder / "bad.cell.json").write_text(json.dumps(bad))
    sim.add_obstacle(box("kept", (0.4, 0.3, 0.2)))
    future = ui.cell.load_file("bad", browser.handle)
    assert future is not None and future.exception(timeout=WAIT_S) is not None
    assert names(sim) == ["kept"]
    assert any("plane points must not lie on one line" in n for n in browser.notifications)

    (folder / "garbage.cell.json").write_text('{"schema_version": 7}')
    assert ui.cell.load_file("garbage", browser.handle) is None
    assert "not a cell file" in browser.notifications[-1]
    assert names(sim) == ["kept"]


def test_the_robot_tab_sets_the_tool_shape_and_shows_the_controllers(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    browser = FakeBrowser(OPERATOR)
    fire(ui.tool_shape.capsules, browser, "30: 0 0 0 -> 0 0 150; 20: 0 0 150 -> 0 60 200")
    sent(ui.tool_shape.submit(browser.handle)).result(timeout=WAIT_S)
    shape = sim.get_tool_shape().shape
    assert [c.radius for c in shape] == pytest.approx([0.03, 0.02])
    assert (shape[1].finish.y, shape[1].finish.z) == pytest.approx((0.06, 0.2))
    pendant_ui.refresh_cell()
    pendant_ui.refresh()
    assert pendant_ui.tool_shape.capsules_shown == 2

    fire(ui.tool_shape.capsules, browser, "30: 0 0 -> 0 0 150")
    assert ui.tool_shape.submit(browser.handle) is None
    assert browser.notifications == [
        "Tool shape not set: capsule 1: each end needs three coordinates (x y z, mm)"
    ]
    assert len(sim.get_tool_shape().shape) == 2

    sim.set_tool_shape(ToolShape(shape=[]))  # a script changes it: the field shows the controller's
    pendant_ui.refresh_cell()
    assert ui.tool_shape.capsules.value == ""


def test_a_jog_towards_an_obstacle_stops_short_of_it(
    pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    q = home_q(sim)
    at = q.copy()
    at[0] += np.radians(30.0)
    sim.add_obstacle(box("fixture", tuple(sim.arm.fk(at)[:3, 3])))
    pendant_ui.refresh_cell()
    request = JogRequest(JogFrame.JOINT, 0, +1, speed_percent=50, step=np.radians(10.0))  # the largest
    assert pendant_ui.jogger.step(request)
    clock.advance(10.0)
    for _ in range(5):  # 60° of steps towards a fixture 30° away: the last ones shortened, then refused
        if not pendant_ui.jogger.step(request):
            break
        clock.advance(10.0)
    reached = home_q(sim)
    assert 5.0 < np.degrees(reached[0] - q[0]) < 30.0
    assert pendant_ui.cell_model is not None and not pendant_ui.cell_model.collides(reached)
