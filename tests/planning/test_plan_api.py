"""POST /pendant/plan over real HTTP against `pendant --no-ui` (the simulator on a fast clock): a straight
Move J through a box is refused, the planned path to the same target runs as one PUT /run/joint/poses along
the segments the planner checked and ends
there; bad input is refused with the reason before any planning, and nothing moves."""

from __future__ import annotations

import httpx
import numpy as np
import pytest

from pendant.kinematics import ArmModel
from pendant.kinematics.cell_shapes import cell_check
from pendant.planning import path_is_clear
from pendant.planning.scenes import BOX, FLANGE
from tests.support.planned_runs import along_segments
from tests.support.waiting import SAFETY_NET_S, wait_idle

ANGLE_TOL_DEG = 0.01
MOTION_TIMEOUT_S = SAFETY_NET_S
DENSE_RECHECK_RAD = np.radians(0.25)  # finer than the planner's own 0.5 degree re-check
SLOW_PERCENT = 100
# The longest search the API allows (the default is 1 s of wall clock): a pendant starved of CPU (the pass
# behind the timed tests runs at nice 19) still finds the path; a search ends as soon as it has one.
BUDGET_S = 10.0


@pytest.fixture(scope="module")
def api(fast_api: httpx.Client) -> httpx.Client:
    _go(fast_api, BOX.start_deg)  # the box stands where the arm starts (home), which would refuse it
    added = fast_api.put("/environment", json=BOX.obstacles[0].model_dump(mode="json"))
    assert added.status_code == 200, added.text
    return fast_api


def _go(api: httpx.Client, degrees: tuple[float, ...] | list[float]) -> None:
    """Move there around whatever is in the way: planned, then run."""
    planned = api.post("/pendant/plan", json={"target": {"angles": list(degrees)}, "budget_s": BUDGET_S})
    assert planned.status_code == 200, planned.text
    run = api.put(
        "/run/joint/poses",
        json=along_segments([w["angles"] for w in planned.json()["waypoints"][1:]], SLOW_PERCENT),
    )
    assert run.status_code == 200, run.text
    wait_idle(api, MOTION_TIMEOUT_S)


def _pose(api: httpx.Client) -> np.ndarray:
    return np.array(api.get("/pose").json()["angles"])


def test_a_straight_move_through_the_box_is_refused_and_the_planned_one_runs_to_the_target(
    api: httpx.Client,
) -> None:
    _go(api, BOX.start_deg)
    straight = api.put("/pose", json={"angles": list(BOX.target_deg)}, params={"speed": SLOW_PERCENT})
    assert straight.status_code == 412
    assert "Collision" in straight.json()
    assert np.allclose(_pose(api), BOX.start_deg, atol=ANGLE_TOL_DEG)  # refused: nothing moved

    planned = api.post(
        "/pendant/plan", json={"target": {"angles": list(BOX.target_deg)}, "budget_s": BUDGET_S}
    )
    assert planned.status_code == 200, planned.text
    body = planned.json()
    waypoints = [w["angles"] for w in body["waypoints"]]
    assert np.allclose(waypoints[0], BOX.start_deg) and np.allclose(waypoints[-1], BOX.target_deg)
    assert len(waypoints) >= 3  # around the box, not through it
    assert body["length_deg"] > 120.0 and body["planning_ms"] > 0.0
    assert np.allclose(_pose(api), BOX.start_deg, atol=ANGLE_TOL_DEG)  # planning moved nothing
    arm = ArmModel.load("pulse75")
    assert path_is_clear(
        cell_check(arm, BOX.obstacles, BOX.tool_shape, FLANGE), np.radians(waypoints), DENSE_RECHECK_RAD
    )

    run = api.put("/run/joint/poses", json=along_segments(waypoints[1:], SLOW_PERCENT))
    assert run.status_code == 200, run.text
    wait_idle(api, MOTION_TIMEOUT_S)
    assert np.allclose(_pose(api), BOX.target_deg, atol=ANGLE_TOL_DEG)
    assert api.get("/status/motion").json() == "IDLE"


def test_a_position_target_is_planned_to_a_clear_configuration_that_reaches_it(api: httpx.Client) -> None:
    arm = ArmModel.load("pulse75")
    _go(api, BOX.target_deg)
    position = api.get("/position").json()
    _go(api, BOX.start_deg)
    planned = api.post("/pendant/plan", json={"target": {"position": position}, "budget_s": BUDGET_S})
    assert planned.status_code == 200, planned.text
    last = np.radians(planned.json()["waypoints"][-1]["angles"])
    tcp = api.get("/tool").json()["point"]
    reached = arm.fk(last)[:3, 3] + arm.fk(last)[:3, :3] @ np.array([tcp["x"], tcp["y"], tcp["z"]])
    assert np.allclose(reached, [position["point"][k] for k in "xyz"], atol=1e-5)


@pytest.mark.parametrize(
    ("body", "status", "reason"),
    [
        ({"target": {"angles": [400, -90, 90, -90, -90, 0]}}, 412, "outside the joint limits (joint 1"),
        ({"target": {"angles": [0, -90, 90, -90, -90]}}, 400, "target.angles"),
        ({"target": {"angles": [0, -90, 90, -90, -90, 0]}, "budget_s": 11}, 400, "budget_s"),
        ({"target": {"angles": [0, -90, 90, -90, -90, 0]}, "budget_s": 0}, 400, "budget_s"),
        ({"target": {}}, 400, "exactly one of angles and position"),
        (  # the shoulder tipped into the floor: never a start (a start touching an obstacle may be)
            {"target": {"angles": list(BOX.target_deg)}, "from": {"angles": [0, 20, 0, 0, 0, 0]}},
            412,
            "the start itself is touching the floor or itself",
        ),
        ({"target": {"angles": [0, -90, 90, -90, -90, 0]}}, 412, "the target itself is inside 'box'"),
    ],
)
def test_bad_input_is_answered_with_the_reason_before_any_planning(
    api: httpx.Client, body: dict[str, object], status: int, reason: str
) -> None:
    _go(api, BOX.start_deg)
    answer = api.post("/pendant/plan", json=body)
    assert answer.status_code == status
    assert reason in answer.json()
    assert np.allclose(_pose(api), BOX.start_deg, atol=ANGLE_TOL_DEG)


def test_nan_is_refused_as_a_malformed_body(api: httpx.Client) -> None:
    answer = api.post(
        "/pendant/plan",
        content=b'{"target": {"angles": [NaN, -90, 90, -90, -90, 0]}}',
        headers={"content-type": "application/json"},
    )
    assert answer.status_code == 400


def test_the_route_is_documented_in_the_openapi(api: httpx.Client) -> None:
    operation = api.get("/openapi.json").json()["paths"]["/pendant/plan"]["post"]
    assert "PUT /run/joint/poses" in operation["description"]
    assert {"200", "400", "412"} <= set(operation["responses"])
