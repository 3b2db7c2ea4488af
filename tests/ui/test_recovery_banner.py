"""The banner under Freeze, headless (issue 25): every fault shows what happened, since when and the button
that gets the arm going again; pressing it gets there; the event log keeps the cause and the choice. In a
fault the joints stay on screen (greyed, last known); a Go to refused for a collision names the obstacle and
turns the ghost red."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from pendant.cell.collision_names import name_collision
from pendant.cell.geometry import CellModel
from pendant.controller import MotionStatus, Pose
from pendant.controller.cell_types import BoxObstacle, ToolShape
from pendant.controller.types import Point, Position, Rotation
from pendant.eventlog import EventLog
from pendant.eventquery import EventQuery
from pendant.kinematics import ArmModel
from pendant.kinematics.collision_words import link_words
from pendant.program import MoveStep, Program, Waypoint
from pendant.sim import Fault, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.recovery import Recovery
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S


def wait_for(condition: Callable[[], bool], what: str) -> None:
    deadline = time.monotonic() + WAIT_S
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.02)


def box(name: str, xyz: np.ndarray, side: float = 0.1) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=side, y=side, z=side),
        centerPosition=Position(
            point=Point(x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2])),
            rotation=Rotation(roll=0, pitch=0, yaw=0),
        ),
    )


def refresh(page: PendantUI) -> None:
    page.refresh_cell()
    page.refresh()


def banner_buttons(ui: ClientSession) -> list[str]:
    assert ui.banner is not None
    return [b.label for b in ui.banner.buttons if b.visible]


def press(ui: ClientSession, label: str) -> None:
    assert ui.banner is not None
    fire(next(b for b in ui.banner.buttons if b.visible and b.label == label), FakeBrowser(OPERATOR))


def logged(page: PendantUI) -> list[str]:
    return [f"{e.source}: {e.message}" for e in page.events.search(EventQuery())]


def test_no_banner_while_all_is_well(pendant_ui: PendantUI, ui: ClientSession) -> None:
    refresh(pendant_ui)
    assert ui.banner is not None and ui.banner.view is None
    assert banner_buttons(ui) == []


def test_a_controller_error_says_why_and_recover_brings_it_back(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.inject_fault(Fault.ERROR)
    refresh(pendant_ui)
    view = ui.banner.view if ui.banner else None
    assert view is not None and view.title == "Controller error"
    assert view.detail == "Controller error: the arm stopped and froze"  # the controller's own reason
    assert banner_buttons(ui) == ["Recover"]
    press(ui, "Recover")
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "the recovery")
    refresh(pendant_ui)
    assert ui.banner is not None and ui.banner.view is None
    log = logged(pendant_ui)
    assert any(line.startswith("banner: Controller error: Controller error: the arm stopped") for line in log)
    assert any("Recover (banner)" in line for line in log)  # the operator's choice


def test_emergency_keeps_the_joints_and_the_cell_and_names_the_way_out(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.add_obstacle(box("Fixture", np.array([0.5, -0.4, 0.1])))
    refresh(pendant_ui)
    j1 = f"{sim.get_pose().angles[0]:.1f}°"
    sim.inject_fault(Fault.EMERGENCY)
    refresh(pendant_ui)
    view = ui.banner.view if ui.banner else None
    assert view is not None and view.title == "EMERGENCY"
    assert "Release the emergency stop on the arm, then Recover" in view.next_step
    assert banner_buttons(ui) == ["Reset simulator (keeps the cell)"]
    status = ui.status.content
    assert 'id="last-known"' in status and "last known, " in status and j1 in status  # greyed, not blank
    assert 'id="tcp"' in status
    press(ui, "Reset simulator (keeps the cell)")
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "the reset")
    refresh(pendant_ui)
    assert ui.banner is not None and ui.banner.view is None
    assert [o.name for o in sim.get_obstacles()] == ["Fixture"]  # the cell is kept
    assert "last known" not in ui.status.content


def test_a_protective_stop_is_named_and_recover_leaves_it(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    sim.stop()
    refresh(pendant_ui)
    view = ui.banner.view if ui.banner else None
    assert view is not None and view.title == "Protective stop" and "Protective stop" in view.detail
    assert banner_buttons(ui) == ["Recover"]
    # The banner alone says it (the status panel keeps its ERROR readout, no second "Recover to continue").
    assert ">ERROR<" in ui.status.content and "Recover to continue" not in ui.status.content
    assert not ui.status.recover.visible
    press(ui, "Recover")
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "the recovery")


def test_free_drive_offers_the_way_back(pendant_ui: PendantUI, ui: ClientSession, sim: SimController) -> None:
    sim.zg_on()
    refresh(pendant_ui)
    assert banner_buttons(ui) == ["Leave free drive"]
    press(ui, "Leave free drive")
    wait_for(lambda: sim.get_motion_status() is MotionStatus.IDLE, "free drive off")


def test_go_to_refused_for_a_collision_names_the_obstacle_and_shows_a_red_ghost(
    pendant_ui: PendantUI, ui: ClientSession, sim: SimController
) -> None:
    operator = FakeBrowser(OPERATOR)
    fire(ui.program.record, operator)
    assert ui.program.pending is not None
    ui.program.pending.result(timeout=WAIT_S)  # P1 at home
    q = np.radians(sim.get_pose().angles)
    sim.relax()  # move the arm away by hand, then put a box where P1 is
    away = q.copy()
    away[0] += np.radians(90.0)
    sim.move_by_hand(Pose(angles=list(np.degrees(away))))
    sim.zg_off()
    sim.add_obstacle(box("Box", sim.arm.fk(q)[:3, 3]))
    refresh(pendant_ui)
    fire(ui.program.waypoints.go_to, operator)
    wait_for(lambda: bool(operator.notifications), "the refusal")
    refusal = operator.notifications[-1]  # the controller names it now; the page's words where it does not
    assert "Collision detected" in refusal and "'Box'" in refusal
    assert ui.program.waypoints.refused.shown_q is not None
    assert ui.program.waypoints.refused.hits == ("Box",)


def test_a_self_collision_names_the_two_links(sim: SimController) -> None:
    arm: ArmModel = sim.arm
    folded = np.radians([0.0, -90.0, 170.0, 0.0, 0.0, 0.0])
    assert arm.in_collision(folded)  # folded onto itself
    named = name_collision(arm, folded)
    assert named.reason is not None and " would touch " in named.reason
    assert link_words([("link2_1", "link5_0")]) == "Collision detected: link2 would touch link5"
    assert link_words([("floor", "link6_0")]) == "Collision detected: link6 would touch the floor"


def test_a_blended_group_refused_whole_names_the_step_in_the_way(sim: SimController) -> None:
    """The controller refuses a blended path whole, at its first line: the page finds the move whose target
    is in the box, names the box, and keeps that pose for the banner's red ghost."""
    poses = {"A": [20.0, -90.0, 90.0, -90.0, -90.0, 0.0], "B": [-20.0, -80.0, 80.0, -90.0, -90.0, 0.0]}
    zero = Position(point=Point(x=0, y=0, z=0), rotation=Rotation(roll=0, pitch=0, yaw=0))
    program = Program(
        name="blended",
        waypoints=tuple(Waypoint(name=n, pose=Pose(angles=a), position=zero) for n, a in poses.items()),
        steps=tuple(MoveStep(waypoint=n, speed=50.0) for n in poses),
    )
    q_b = np.radians(poses["B"])
    cell = CellModel(sim.arm, [box("Box", sim.arm.fk(q_b)[:3, 3], side=0.08)], ToolShape(shape=[]))
    recovery = Recovery(
        EventLog(), sim.arm, simulator=True, cell=lambda: cell, current_q=lambda: np.radians(poses["A"])
    )
    assert recovery.explain_step_failure(program, 0, 1, "Collision detected") == (
        "Collision detected: the arm would touch 'Box'"
    )
    assert recovery.refused_q is not None and np.allclose(recovery.refused_q, q_b)
    assert recovery.refused_obstacles == ("Box",)
    assert recovery.explain_step_failure(program, 0, 1, "Robot does not respond") == "Robot does not respond"
