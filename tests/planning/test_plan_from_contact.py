"""POST /pendant/plan from a pose in contact, over real HTTP against `pendant --no-ui`: Rozum's README wall
(example 10) touches the wrist at the power-on pose, the controller takes it, and a plan from there backs
out of the wall first (never deeper in), then goes round; the waypoints run as one PUT /run/joint/poses along
the checked segments."""

from __future__ import annotations

import httpx
import numpy as np
import pytest

from pendant.controller.cell_types import PlaneObstacle, ToolShape
from pendant.controller.types import Point
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_shapes import cell_check
from pendant.kinematics.contact import CONTACT_DEEPER_TOLERANCE_M
from pendant.planning import path_is_clear
from pendant.planning.scenes import FLANGE
from tests.support.planned_runs import along_segments
from tests.support.waiting import SAFETY_NET_S, wait_idle

README_WALL = PlaneObstacle(
    obstacleType="PLANE",
    name="wall",
    points=[Point(x=-0.5, y=0.4, z=0.0), Point(x=-0.5, y=0.0, z=0.0), Point(x=-0.5, y=0.0, z=0.1)],
)
HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # the power-on pose: the wrist is 13 mm into the wall
ROUND = [-60.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # the other way round: straight there stays in the wall
ANGLE_TOL_DEG = 0.01
MOTION_TIMEOUT_S = SAFETY_NET_S
RUN_PERCENT = 50.0
SAMPLE_RAD = np.radians(0.25)


@pytest.fixture(scope="module")
def api(fast_api: httpx.Client) -> httpx.Client:
    return fast_api


def test_a_plan_from_the_wall_backs_out_first_and_runs(api: httpx.Client) -> None:
    assert api.get("/pose").json()["angles"] == HOME
    added = api.put("/environment", json=README_WALL.model_dump(mode="json"))
    assert added.status_code == 200 and "touching the arm" in added.text
    straight = api.put("/pose", json={"angles": ROUND}, params={"speed": 100})
    assert straight.status_code == 412 and "deeper into 'wall'" in straight.text  # refused: nothing moved

    planned = api.post(
        "/pendant/plan", json={"target": {"angles": ROUND}, "budget_s": 10.0}
    )  # the most: see test_plan_api
    assert planned.status_code == 200, planned.text
    waypoints = np.radians([w["angles"] for w in planned.json()["waypoints"]])
    assert np.allclose(np.degrees(waypoints[0]), HOME) and np.allclose(np.degrees(waypoints[-1]), ROUND)
    check = cell_check(ArmModel.load("pulse75"), [README_WALL], ToolShape(shape=[]), FLANGE)
    # The first leg leaves the wall, never deeper than where it started; the rest touches nothing.
    leg = waypoints[0] + np.linspace(0.0, 1.0, 200)[:, None] * (waypoints[1] - waypoints[0])
    depths = [check.contacts(q).get("wall") for q in leg]
    start_depth = depths[0].depth_m if depths[0] is not None else 0.0
    assert start_depth > 0.005 and depths[-1] is None
    assert all(d is None or d.depth_m <= start_depth + CONTACT_DEEPER_TOLERANCE_M for d in depths)
    assert path_is_clear(check, waypoints[1:], SAMPLE_RAD)

    run = api.put("/run/joint/poses", json=along_segments(np.degrees(waypoints[1:]).tolist(), RUN_PERCENT))
    assert run.status_code == 200, run.text
    wait_idle(api, MOTION_TIMEOUT_S)
    assert np.allclose(api.get("/pose").json()["angles"], ROUND, atol=ANGLE_TOL_DEG)
