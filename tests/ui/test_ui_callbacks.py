"""The pendant page's callbacks, headless: a real viser server on loopback, no browser, a fake clock."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionStatus, Pose, SignalLevel
from pendant.controller.errors import (
    MSG_COLLISION,
    MSG_EMERGENCY,
    MSG_NOT_RESPONDING,
    MSG_UNREACHABLE_POSITION,
)
from pendant.controller.types import MotionType, Point, Rotation, Tool
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim import FakeClock, Fault, SimController
from pendant.ui.app import PendantUI
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.session import ClientSession
from pendant.ui.page.status_panel import render_status
from tests.support.pages import pendant_page, sent

TOOL_LENGTH_M = 0.12
ANGLE_TOL_DEG = 1e-6
FAR_FROM_THE_WORK_M = 100.0
FUTURE_TIMEOUT_S = 60.0  # a safety net: a thread starved of CPU (nice 19, a loaded machine) may take seconds


def pose_deg(sim: SimController) -> np.ndarray:
    return np.asarray(sim.get_pose().angles)


def test_until_the_operator_sets_a_target_it_follows_the_arm_with_no_ghost_and_nothing_to_run(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    panel = ui.target_panel
    assert panel.check.q is not None
    np.testing.assert_allclose(np.degrees(panel.check.q), pose_deg(sim), atol=ANGLE_TOL_DEG)
    assert panel.ghost_shown is None and panel.move_j.disabled and panel.move_l.disabled

    sim.set_pose(Pose(angles=[30.0, -80.0, 80.0, -90.0, -90.0, 0.0]), MotionParams(speed=100.0))
    clock.advance(0.2)
    pendant_ui.refresh(with_io=True)
    assert not panel.gizmo_shown, "not chased while the arm moves"
    # far out of the view, yet not made invisible: a page would unmount it, and compile its shaders again
    assert panel.gizmo_in_scene and np.linalg.norm(panel.gizmo_position) > FAR_FROM_THE_WORK_M
    clock.advance(30.0)
    pendant_ui.refresh(with_io=True)
    assert panel.check.q is not None
    np.testing.assert_allclose(np.degrees(panel.check.q), pose_deg(sim), atol=ANGLE_TOL_DEG)
    assert panel.gizmo_shown and panel.ghost_shown is None, "back at the TCP; no stale ghost"

    target = np.radians(pose_deg(sim) + np.array([-20.0, 0.0, 0.0, 0.0, 0.0, 0.0]))
    assert panel.set_joint_target(target).ok  # the operator moves a slider: now it is a target
    assert panel.ghost_shown is True and not panel.move_j.disabled
    pendant_ui.refresh(with_io=True)
    np.testing.assert_allclose(panel.check.q, target, atol=1e-12)  # it stays where it was set

    panel.reset_to_current()  # "Target = current": follow the arm again
    assert panel.ghost_shown is None and panel.move_j.disabled


def test_unreachable_drag_target_is_red_says_why_and_cannot_run(
    ui: ClientSession, sim: SimController
) -> None:
    T = sim.arm.fk(np.radians(pose_deg(sim)))
    T[:3, 3] = (2.0, 0.0, 0.5)  # two metres out: beyond any PULSE
    check = ui.target_panel.set_flange_target(T)
    assert check.reason == MSG_UNREACHABLE_POSITION
    assert ui.target_panel.ghost_shown is False  # the red ghost, not the blue one
    assert ui.target_panel.move_j.disabled and ui.target_panel.move_l.disabled
    assert MSG_UNREACHABLE_POSITION in ui.target_panel.reason.content
    before = pose_deg(sim)
    assert ui.target_panel.run(MotionType.JOINT) is None
    np.testing.assert_allclose(pose_deg(sim), before, atol=ANGLE_TOL_DEG)


def test_colliding_slider_target_is_refused(ui: ClientSession) -> None:
    q = np.radians([0.0, -90.0, 170.0, -90.0, -90.0, 0.0])  # forearm folded into the upper arm
    check = ui.target_panel.set_joint_target(q)
    assert check.reason == f"{MSG_COLLISION}: link1 would touch link3"  # the two links named
    assert ui.target_panel.ghost_shown is False
    assert ui.target_panel.move_j.disabled


def test_move_j_from_sliders_reaches_the_target(
    ui: ClientSession, sim: SimController, clock: FakeClock
) -> None:
    target_deg = np.array([30.0, -80.0, 60.0, -70.0, -90.0, 15.0])
    assert ui.target_panel.set_joint_target(np.radians(target_deg)).ok
    sent(ui.target_panel.run(MotionType.JOINT)).result(timeout=FUTURE_TIMEOUT_S)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    clock.advance(30.0)
    np.testing.assert_allclose(pose_deg(sim), target_deg, atol=1e-6)


def test_move_l_from_a_dragged_gizmo_reaches_it(
    ui: ClientSession, sim: SimController, clock: FakeClock
) -> None:
    T = sim.arm.fk(np.radians(pose_deg(sim)))
    T[:3, 3] += (0.05, 0.05, -0.05)
    assert ui.target_panel.set_flange_target(T).ok
    sent(ui.target_panel.run(MotionType.LINEAR)).result(timeout=FUTURE_TIMEOUT_S)
    clock.advance(30.0)
    np.testing.assert_allclose(sim.arm.fk(np.radians(pose_deg(sim)))[:3, 3], T[:3, 3], atol=1e-6)


def test_with_a_tool_the_gizmo_holds_its_tcp_and_a_drag_moves_the_tcp_there(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController, clock: FakeClock
) -> None:
    sim.set_tool(
        Tool(
            name="probe",
            point=Point(x=0.0, y=0.0, z=TOOL_LENGTH_M),
            rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
            radius=0.01,
        )
    )
    pendant_ui.refresh(with_io=True)  # the page reads the tool with the IO
    ui.target_panel.reset_to_current()
    tcp = sim.get_position().point  # the zero point is the base by default
    np.testing.assert_allclose(ui.target_panel.gizmo_position, (tcp.x, tcp.y, tcp.z), atol=1e-9)

    T_base_tcp = position_to_matrix(sim.get_position())
    T_base_tcp[:3, 3] += (0.05, 0.0, -0.05)
    assert ui.target_panel.set_tcp_target(T_base_tcp).ok
    sent(ui.target_panel.run(MotionType.LINEAR)).result(timeout=FUTURE_TIMEOUT_S)
    clock.advance(30.0)
    moved = sim.get_position().point
    np.testing.assert_allclose((moved.x, moved.y, moved.z), T_base_tcp[:3, 3], atol=1e-6)


def test_output_toggle_from_the_page_sets_the_controller_output(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    pendant_ui.runner.submit("DO2", lambda c: c.set_output(2, SignalLevel.HIGH), None).result(
        FUTURE_TIMEOUT_S
    )
    pendant_ui.refresh()
    assert ui.io.outputs[2].value is True
    assert sim.get_output(2) is SignalLevel.HIGH


def test_error_state_is_shown_as_a_red_banner_and_recover_clears_it(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    sim.inject_fault(Fault.ERROR)
    pendant_ui.refresh()
    assert "ERROR" in ui.status.content and "#e03131" in ui.status.content
    pendant_ui.runner.submit("Recover", lambda c: c.recover(), None).result(FUTURE_TIMEOUT_S)
    assert pendant_ui.refresh().motion_status is MotionStatus.IDLE


def test_emergency_is_a_red_emergency_banner_not_offline(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    sim.inject_fault(Fault.EMERGENCY)
    snapshot = pendant_ui.refresh()
    assert snapshot.motion_status is MotionStatus.EMERGENCY and snapshot.online
    assert ">EMERGENCY<" in ui.status.content and "#c92a2a" in ui.status.content
    assert "OFFLINE" not in ui.status.content and "online" in ui.status.content
    assert MSG_EMERGENCY in ui.status.content


def test_a_controller_that_does_not_respond_is_online_with_a_red_banner(
    ui: ClientSession, pendant_ui: PendantUI, sim: SimController
) -> None:
    sim.inject_fault(Fault.NO_RESPONSE)
    pendant_ui.refresh()
    assert ">NO RESPONSE<" in ui.status.content and "#e03131" in ui.status.content
    assert MSG_NOT_RESPONDING in ui.status.content and "offline" not in ui.status.content


def test_the_robot_id_appears_once_a_controller_that_was_down_at_start_answers(sim: SimController) -> None:
    sim.inject_fault(Fault.NO_RESPONSE)
    with pendant_page(sim, sim.arm) as page:
        assert page.refresh().robot_id == ""
        sim.reset()
        assert page.refresh(with_io=True).robot_id == sim.get_robot_id() != ""


def test_invalid_tool_form_is_refused_before_anything_is_sent(ui: ClientSession, sim: SimController) -> None:
    before = sim.get_tool()
    ui.settings.tool_name.value = "   "  # type: ignore[misc]  # viser 1.1.1: its setter is not beside the getter
    assert not ui.settings.submit_tool(None)
    ui.settings.tool_name.value = "gripper"  # type: ignore[misc]  # viser 1.1.1: its setter is not beside the getter
    ui.settings.tool_xyz.show((0.0, 0.0, 5000.0))
    assert not ui.settings.submit_tool(None)
    assert sim.get_tool() == before


def test_valid_tool_form_sets_the_tool(ui: ClientSession, pendant_ui: PendantUI, sim: SimController) -> None:
    ui.settings.tool_name.value = "gripper"  # type: ignore[misc]  # viser 1.1.1: its setter is not beside the getter
    ui.settings.tool_xyz.show((0.0, 0.0, 120.0))
    assert ui.settings.submit_tool(None)
    pendant_ui.runner.submit("sync", lambda c: None, None).result(FUTURE_TIMEOUT_S)
    tool = sim.get_tool()
    assert tool.name == "gripper"
    assert tool.point.z == pytest.approx(0.12)


def test_a_gripper_the_controller_cannot_report_is_shown_as_unknown() -> None:
    assert "gripper <b>unknown</b>" in render_status(Snapshot(taken_at=0.0, gripper_opening=None), "robot")
    assert "gripper <b>open</b>" in render_status(Snapshot(taken_at=0.0, gripper_opening=1.0), "robot")


def test_a_round_trip_under_10_ms_leaves_the_status_block_as_it_was() -> None:
    def block(latency_s: float) -> str:
        return render_status(Snapshot(taken_at=0.0, online=True, latency_s=latency_s), "simulator")

    assert block(0.0004) == block(0.0016) == block(0.0093)  # nothing for a browser to redraw at rest
    assert "online · " not in block(0.0016)
    assert "online · 50 ms" in block(0.047) and block(0.047) == block(0.052)
