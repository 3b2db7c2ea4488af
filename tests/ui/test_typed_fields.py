"""Typed fields (issue 31, item 3): the text the page commits is read as it is; an empty box, letters or a
value out of range is marked under the box and refuses the action that needs it, with the reason, and
nothing moves or is added (an old value is never used silently)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.controller import MotionParams, MotionType, Pose
from pendant.planning.scenes import BOX
from pendant.sim import FakeClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.kit.typed_field import format_number, parse_number
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, FakeBrowser, fire
from tests.support.sim_sampling import finish_motion, pose_deg
from tests.support.waiting import SAFETY_NET_S, wait_until


@pytest.fixture
def operator() -> FakeBrowser:
    return FakeBrowser(OPERATOR)


@pytest.mark.parametrize(
    ("text", "reason"),
    [
        ("", "empty: type a number"),
        ("   ", "empty: type a number"),
        ("abc", "'abc' is not a number"),
        ("-6-9", "'-6-9' is not a number"),
        ("nan", "'nan' is not a number"),
        ("1e999", "'1e999' is not a number"),
        ("400", "out of range: from -360 to 360"),
    ],
)
def test_what_is_not_a_usable_number_says_why(text: str, reason: str) -> None:
    with pytest.raises(ValueError, match=f"^{reason}$"):
        parse_number(text, -360.0, 360.0)


@pytest.mark.parametrize(
    ("text", "value"), [("-69.3", -69.3), (" 125.9 ", 125.9), ("-0", 0.0), ("1e2", 100.0)]
)
def test_a_number_is_read_as_typed(text: str, value: float) -> None:
    assert parse_number(text, -360.0, 360.0) == value


def test_the_server_writes_numbers_without_trailing_zeros() -> None:
    assert [format_number(v, 1) for v in (20.0, -69.3, -0.04, 125.94)] == ["20", "-69.3", "0", "125.9"]


def test_an_empty_j1_refuses_move_j_with_the_reason_and_the_arm_stays(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    panel = ui.target_panel
    before = pose_deg(sim)
    fire(panel.joints[1], operator, "-80")  # a target is set: Move J would run it
    assert panel.executable
    fire(panel.joints[0], operator, "")
    assert panel.joints[0].reason == "empty: type a number"
    assert panel.joints[0]._mark.visible and "empty: type a number" in panel.joints[0]._mark.content
    assert panel.move_j.disabled and "J1: empty" in panel.reason.content
    assert panel.run(MotionType.JOINT, operator) is None  # type: ignore[arg-type]  # a fake browser
    finish_motion(sim, clock)
    np.testing.assert_array_equal(pose_deg(sim), before)
    assert operator.notifications[-1] == "Move J refused: J1: empty: type a number"


def test_a_typed_j1_is_the_angle_move_j_sends(
    ui: ClientSession, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    panel = ui.target_panel
    fire(panel.joints[0], operator, "-69.3")
    future = panel.run(MotionType.JOINT, operator)  # type: ignore[arg-type]  # a fake browser
    assert future is not None
    future.result(timeout=SAFETY_NET_S)
    finish_motion(sim, clock)
    assert math.isclose(pose_deg(sim)[0], -69.3, abs_tol=1e-6)


def test_letters_in_the_move_speed_refuse_move_j(ui: ClientSession, operator: FakeBrowser) -> None:
    panel = ui.target_panel
    fire(panel.joints[0], operator, "-30")
    fire(panel.speed, operator, "fast")
    assert panel.run(MotionType.JOINT, operator) is None  # type: ignore[arg-type]  # a fake browser
    assert operator.notifications[-1] == "Move J refused: Move speed %: 'fast' is not a number"


def test_an_empty_loops_refuses_run(ui: ClientSession, operator: FakeBrowser) -> None:
    run = ui.program.run_section
    fire(run.loops, operator, "")
    fire(run.run, operator)
    assert operator.notifications[-1] == "Run refused: Loops: empty: type a number"
    fire(run.loops, operator, "2.5")
    fire(run.run, operator)
    assert operator.notifications[-1] == "Run refused: Loops: must be a whole number"


def test_an_emptied_position_adds_no_obstacle(
    ui: ClientSession, operator: FakeBrowser, sim: SimController
) -> None:
    fire(ui.cell.at, operator, "")
    assert ui.cell.submit(operator, add=True) is None  # type: ignore[arg-type]  # a fake browser
    assert (
        operator.notifications[-1] == "Obstacle not added: Position mm: empty: type 3 numbers, e.g. 0, 0, 0"
    )
    fire(ui.cell.at, operator, "400, , 100")  # X and Z only
    assert ui.cell.submit(operator, add=True) is None  # type: ignore[arg-type]
    assert "Position mm: type 3 numbers" in operator.notifications[-1]
    assert sim.get_obstacles() == []


def test_a_target_reached_by_a_planned_move_is_not_cannot_execute(
    ui: ClientSession, pendant_ui: PendantUI, operator: FakeBrowser, sim: SimController, clock: FakeClock
) -> None:
    panel = ui.target_panel
    sim.set_pose(Pose(angles=list(BOX.start_deg)), MotionParams(speed=100.0))
    finish_motion(sim, clock)
    for obstacle in BOX.obstacles:
        sim.add_obstacle(obstacle)
    pendant_ui.refresh(with_io=True)
    pendant_ui.refresh_cell()
    for field, angle in zip(panel.joints, BOX.target_deg, strict=True):
        fire(field, operator, f"{angle:.1f}")
    assert panel.reason.content.startswith("**No straight path:**") and "'box'" in panel.reason.content
    planned = panel.plan.plan(operator)  # type: ignore[arg-type]  # a fake browser
    assert planned is not None
    planned.result(timeout=30.0)
    # The plan's done-callback keeps the path, then draws its course: wait for both.
    wait_until(lambda: panel.plan.path is not None and panel.plan.course_shown, SAFETY_NET_S, "a plan drawn")
    moved = panel.plan.run(operator)  # type: ignore[arg-type]
    assert moved is not None
    moved.result(timeout=SAFETY_NET_S)
    finish_motion(sim, clock)
    pendant_ui.refresh(with_io=True)  # the arm at rest at the target: the page's verdict is made again
    np.testing.assert_allclose(pose_deg(sim), np.round(BOX.target_deg, 1), atol=1e-6)
    assert panel.reason.content == "**Target reached** — the arm is there."
    assert panel.plan.path is None and not panel.plan.course_shown and panel.plan.status.content == ""
