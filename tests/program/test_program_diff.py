"""The diff of two versions lists exactly the changes made, in the operator's words."""

from __future__ import annotations

import pytest

from pendant.controller import SignalLevel
from pendant.program import LoopStep, MoveStep, Program, WaitInputStep, WaitStep
from pendant.program.diff import diff_programs
from tests.support.program_history import pick_program, waypoint

DISTANCE_TOL_MM = 1e-6


def test_identical_programs_have_no_changes() -> None:
    change = diff_programs(pick_program(), pick_program())
    assert change.lines == () and change.moved == () and change.summary() == "no change"


def test_every_kind_of_change_is_listed_once_and_nothing_else() -> None:
    old = pick_program()
    new = Program(
        name="pick",
        waypoints=(
            waypoint("P1", 400.0),
            waypoint("P2", 450.0),
            waypoint("P3", 512.0, yaw_deg=0.5),  # re-taught 12 mm further in X, turned half a degree
        ),
        steps=(
            MoveStep(waypoint="P1", speed=40.0),  # was 20 %
            MoveStep(waypoint="P3"),  # the move to P2 is gone
            LoopStep(times=4, body=(WaitStep(ms=500),)),  # 3 times before
            WaitInputStep(port=2, level=SignalLevel.HIGH),  # new
        ),
    )
    change = diff_programs(old, new)
    assert change.lines == (
        "P3 moved +12.0 mm in X and turned +0.5° in yaw",
        "step 1 (Move J to P1 @ 40%): speed 20 -> 40 %",
        "step 2 (Move J to P2 @ 20%) removed",
        "step 3 (Loop 4 times): now 4 times (was 3)",
        "step 5 (Wait DI2 HIGH (timeout 5000 ms)) added",
    )
    [moved] = change.moved
    assert moved.name == "P3" and moved.distance_mm == pytest.approx(12.0, abs=DISTANCE_TOL_MM)
    assert change.summary() == (
        "P3 moved +12.0 mm in X and turned +0.5° in yaw; "
        "step 1 (Move J to P1 @ 40%): speed 20 -> 40 % (+3 more)"
    )


def test_a_renamed_waypoint_is_followed_through_the_steps() -> None:
    old = pick_program()
    renamed = [w.model_copy(update={"name": "Pick"}) if w.name == "P3" else w for w in old.waypoints]
    steps = [MoveStep(waypoint="Pick") if getattr(s, "waypoint", None) == "P3" else s for s in old.steps]
    new = old.model_copy(update={"waypoints": tuple(renamed), "steps": tuple(steps)})
    assert diff_programs(old, new).lines == ("waypoint P3 renamed to Pick",)


def test_renamed_and_retaught_is_one_waypoint_that_moved() -> None:
    old = pick_program()
    table = (old.waypoints[0], old.waypoints[1], waypoint("Place", 500.0, y_mm=-30.0, z_mm=340.0))
    steps = [MoveStep(waypoint="Place") if getattr(s, "waypoint", None) == "P3" else s for s in old.steps]
    change = diff_programs(old, old.model_copy(update={"waypoints": table, "steps": tuple(steps)}))
    assert change.lines == ("waypoint P3 renamed to Place", "Place moved 50.0 mm (-30.0 in Y, +40.0 in Z)")
    assert change.moved[0].distance_mm == pytest.approx(50.0, abs=DISTANCE_TOL_MM)


def test_a_reordered_step_is_moved_not_removed_and_added() -> None:
    old = pick_program(extra=(WaitStep(ms=100),))
    last = old.steps[-1]
    new = old.model_copy(update={"steps": (last, *old.steps[:-1])})
    assert diff_programs(old, new).lines == ("step 6 (Wait 100 ms) moved to step 1",)


def test_added_and_removed_waypoints() -> None:
    old = pick_program()
    table = (*old.waypoints, waypoint("P4", 600.0, y_mm=100.0))
    new = old.model_copy(update={"waypoints": table})
    assert diff_programs(old, new).lines == ("waypoint P4 added at (600.0, 100.0, 300.0) mm",)
    assert diff_programs(new, old).lines == ("waypoint P4 removed",)
