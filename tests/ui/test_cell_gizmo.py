"""Placing an obstacle with the transform gizmo, headless through viser's own handles: selecting it shows the
gizmo on it, a drag moves the fields, the release sends one change to the controller, and a change the
controller refuses puts the gizmo back and says why."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import pytest
import viser.transforms as vtf

from pendant.controller.cell_types import BoxObstacle, CapsuleObstacle, Obstacle
from pendant.controller.types import MotionParams, Point, Pose
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser, drag, fire
from tests.support.obstacles import box
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S
MM_TOL = 1e-6
DRAG_EVENTS = 30  # a drag of 30 moves: the controller hears one change


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.02)


def pose(xyz: tuple[float, float, float], yaw_deg: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3] = vtf.SO3.from_z_radians(np.radians(yaw_deg)).as_matrix()
    T[:3, 3] = xyz
    return T


def stored(sim: SimController, name: str) -> Obstacle:
    return sim.get_obstacle(name)


def capsule_begin_y(sim: SimController, name: str) -> float:
    capsule = stored(sim, name)
    assert isinstance(capsule, CapsuleObstacle)
    return capsule.begin.y


def centre(obstacle: Obstacle) -> np.ndarray:
    assert isinstance(obstacle, BoxObstacle)
    p = obstacle.centerPosition.point
    return np.array([p.x, p.y, p.z])


@pytest.fixture
def changes(sim: SimController, monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """The obstacles the controller was asked to add or update, in order."""
    asked: list[str] = []
    add = sim.add_obstacle

    def counted(obstacle: Obstacle) -> None:
        asked.append(obstacle.name)
        add(obstacle)

    monkeypatch.setattr(sim, "add_obstacle", counted)
    return asked


def test_a_dragged_obstacle_moves_its_fields_and_reaches_the_controller_on_release(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController, changes: list[str]
) -> None:
    sim.add_obstacle(box("table", (0.5, 0.3, 0.1)))
    changes.clear()  # from here on: the page's
    pendant_ui.refresh_cell()
    gizmo, operator = ui.cell.gizmo, FakeBrowser(OPERATOR)
    assert not gizmo.handle.visible  # nothing selected yet
    fire(ui.cell.selected, operator, "table")
    assert gizmo.handle.visible
    np.testing.assert_allclose(gizmo.handle.position, (0.5, 0.3, 0.1), atol=MM_TOL)

    start = pose((0.5, 0.3, 0.1))
    path = [pose((0.5 + 0.1 * f, 0.3, 0.1), 30.0 * f) for f in np.linspace(0, 1, DRAG_EVENTS)[1:]]
    drag(gizmo.handle, operator, path)
    np.testing.assert_allclose(ui.cell.at.value, (600.0, 300.0, 100.0), atol=MM_TOL)  # the fields followed
    assert ui.cell.rpy.value[2] == pytest.approx(30.0)
    wait_for(lambda: abs(centre(stored(sim, "table"))[0] - 0.6) < MM_TOL, "the table on the controller")
    table = stored(sim, "table")
    assert isinstance(table, BoxObstacle)
    assert np.degrees(table.centerPosition.rotation.yaw) == pytest.approx(30.0)
    assert (table.sides.x, table.sides.y, table.sides.z) == pytest.approx((0.1, 0.1, 0.1))  # size kept
    assert changes == ["table"], "one change per drag, on release"
    assert operator.notifications == []

    pendant_ui.refresh_cell()  # the controller's table: the gizmo rests there for the next drag
    np.testing.assert_allclose(gizmo.handle.position, (0.6, 0.3, 0.1), atol=MM_TOL)
    assert not np.allclose(start, gizmo.resting)


def test_a_placement_the_controller_refuses_puts_the_gizmo_back_and_says_why(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.add_obstacle(box("table", (0.5, 0.3, 0.1)))
    pendant_ui.refresh_cell()
    gizmo, operator = ui.cell.gizmo, FakeBrowser(OPERATOR)
    fire(ui.cell.selected, operator, "table")
    flange = sim.arm.fk(np.radians(sim.get_pose().angles))[:3, 3]
    away = sim.get_pose().angles
    away[0] += 30.0
    sim.set_pose(Pose(angles=away), MotionParams(speed=10.0))  # the fake clock holds the arm in motion
    drag(gizmo.handle, operator, [pose((0.5, 0.3, 0.3)), pose(tuple(flange))])
    wait_for(lambda: bool(operator.notifications), "the refusal")
    assert operator.notifications == [
        "Update obstacle 'table' refused: Collision detected: the obstacle touches the arm or its tool while "
        "it moves (freeze it first)"
    ]
    wait_for(
        lambda: np.allclose(gizmo.handle.position, (0.5, 0.3, 0.1), atol=MM_TOL), "the gizmo back in place"
    )
    np.testing.assert_allclose(ui.cell.at.value, (500.0, 300.0, 100.0), atol=MM_TOL)  # the fields too
    np.testing.assert_allclose(centre(stored(sim, "table")), (0.5, 0.3, 0.1), atol=MM_TOL)  # not moved


def test_a_dragged_capsule_moves_both_ends(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    post = CapsuleObstacle(
        obstacleType="CAPSULE",
        name="post",
        radius=0.04,
        begin=Point(x=0.4, y=0.4, z=0.0),
        finish=Point(x=0.4, y=0.4, z=0.6),
    )
    sim.add_obstacle(post)
    pendant_ui.refresh_cell()
    gizmo, operator = ui.cell.gizmo, FakeBrowser(OPERATOR)
    fire(ui.cell.selected, operator, "post")
    np.testing.assert_allclose(gizmo.handle.position, (0.4, 0.4, 0.3), atol=MM_TOL)  # its middle
    drag(gizmo.handle, operator, [pose((0.4, 0.6, 0.3))])
    wait_for(lambda: abs(capsule_begin_y(sim, "post") - 0.6) < MM_TOL, "the post moved")
    moved = stored(sim, "post")
    assert isinstance(moved, CapsuleObstacle)
    assert (moved.begin.x, moved.begin.y, moved.begin.z) == pytest.approx((0.4, 0.6, 0.0))
    assert (moved.finish.x, moved.finish.y, moved.finish.z) == pytest.approx((0.4, 0.6, 0.6))
    assert moved.radius == pytest.approx(0.04)


def test_a_viewer_gets_no_gizmo(pendant_ui: PendantUI, sim: SimController) -> None:
    sim.add_obstacle(box("table", (0.5, 0.3, 0.1)))
    pendant_ui.refresh_cell()
    viewer = pendant_ui.open_session(pendant_ui.server, client_id=VIEWER)
    fire(viewer.cell.selected, FakeBrowser(VIEWER), "table")
    assert not viewer.cell.gizmo.handle.visible


def test_the_selected_obstacles_fields_and_gizmo_follow_a_scripts_change(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.add_obstacle(box("table", (0.5, 0.3, 0.1)))
    pendant_ui.refresh_cell()
    fire(ui.cell.selected, FakeBrowser(OPERATOR), "table")
    sim.add_obstacle(box("table", (0.5, -0.3, 0.2), side=0.2))  # a script moves and resizes it
    pendant_ui.refresh_cell()
    np.testing.assert_allclose(ui.cell.at.value, (500.0, -300.0, 200.0), atol=MM_TOL)
    np.testing.assert_allclose(ui.cell.size.value, (200.0, 200.0, 200.0), atol=MM_TOL)
    np.testing.assert_allclose(ui.cell.gizmo.handle.position, (0.5, -0.3, 0.2), atol=MM_TOL)

    sim.remove_obstacle("table")  # and deletes it: nothing selected, no gizmo
    pendant_ui.refresh_cell()
    assert ui.cell.selected.value == "(new obstacle)"
    assert not ui.cell.gizmo.handle.visible
