"""The planner over the shipped scenes: every returned path is clear under a dense re-check (finer than the
planner's own), ends exactly at the target as given, and a target that cannot be reached is refused in its
budget rather than answered with a path through something."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.errors import PreconditionFailed
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck
from pendant.planning import MARGIN_M, path_is_clear, plan_joint_path
from pendant.planning.scenes import HOME_DEG, POSTS, SCENES, Scene

DENSE_RAD = np.radians(0.25)
# Generous: a search ends once it has a path, and a machine starved of CPU takes seconds for what takes
# milliseconds alone; benchmarks/ measures the time.
BUDGET_S = 60.0


@pytest.fixture(scope="module")
def arm() -> ArmModel:
    return ArmModel.load("pulse75")


@pytest.mark.parametrize("scene", SCENES, ids=[s.name for s in SCENES])
def test_each_scenes_target_is_planned_around_the_obstacles_and_the_path_is_clear(
    arm: ArmModel, scene: Scene
) -> None:
    check = scene.check(arm)
    start, target = np.radians(scene.start_deg), np.radians(scene.target_deg)
    assert check.path_collides(start, target, np.radians(1.0))  # the straight path would hit something
    path = plan_joint_path(check, start, target, budget_s=BUDGET_S)
    assert np.array_equal(path.waypoints[0], start) and np.array_equal(path.waypoints[-1], target)
    assert path_is_clear(check, path.waypoints, DENSE_RAD)
    assert path.margin_m == MARGIN_M
    assert path_is_clear(check.with_margin(MARGIN_M), path.waypoints)  # the planner's own re-check held
    assert path.length_rad >= float(np.linalg.norm(target - start))


def test_a_joint_with_a_full_turn_each_way_goes_to_the_angle_given_not_an_equivalent(arm: ArmModel) -> None:
    check = CellCheck(arm)
    start = np.radians(HOME_DEG)
    target = start.copy()
    target[0] = np.radians(350.0)  # -10 degrees is the same direction, 360 degrees nearer
    path = plan_joint_path(check, start, target, budget_s=BUDGET_S)
    assert np.degrees(path.waypoints[-1][0]) == pytest.approx(350.0)
    assert len(path.waypoints) == 2  # nothing in the way: the straight joint move


def test_a_search_out_of_time_is_refused_not_answered_with_a_path_through(arm: ArmModel) -> None:
    """The posts' target needs a search; with 5 ms of budget there is none to give: refused, saying so."""
    check = POSTS.check(arm)
    start, target = np.radians(POSTS.start_deg), np.radians(POSTS.target_deg)
    with pytest.raises(PreconditionFailed, match=r"no path found in 0\.005 s"):
        plan_joint_path(check, start, target, budget_s=0.005)
