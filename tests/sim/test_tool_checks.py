"""POST /tool refuses a tool that would already be in the floor (412 "Collision detected"), where the arm is
and where its queued commands leave it, and keeps the old tool; a tool it accepts never blocks a move."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.controller.errors import MSG_COLLISION, Collision
from pendant.controller.types import MotionParams, MotionStatus, MotionType, Point, Pose, Rotation, Tool
from pendant.sim import FakeClock, SimController
from pendant.sim.controller import DEFAULT_TOOL, HOME_POSE_DEG
from tests.support.sim_sampling import ANGLE_TOL_DEG, POS_TOL_M, finish

JOINT_50 = MotionParams(speed=50)
LINEAR_50 = MotionParams(speed=50, motion_type=MotionType.LINEAR)
# How far a sphere is set just inside or just clear of the floor in the boundary test.
FLOOR_MARGIN_M = 1e-6
LIFT_M = 0.01
# At the power-on pose the flange is about 0.485 m above the floor, pointing straight down.
NUDGED_HOME = Pose(angles=[10.0, -90.0, 90.0, -90.0, -90.0, 0.0])
# Flange about 0.18 m above the floor, still pointing down: clear for the bare flange, not for a long tool.
LOW_POSE = Pose(angles=[0.0, -60.0, 120.0, -150.0, -90.0, 0.0])


def _tool(name: str, z: float, radius: float = 0.0) -> Tool:
    return Tool(
        name=name,
        point=Point(x=0.0, y=0.0, z=z),
        rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
        radius=radius,
    )


# Tip about 0.115 m under the floor at the power-on pose.
TOO_LONG = _tool("lance", 0.6)
# Tip well clear, but a sphere this big reaches through the floor.
TOO_WIDE = _tool("ball", 0.0, radius=1.5)
SENSIBLE = _tool("gripper", 0.1, radius=0.05)
# Clear at the power-on pose (tip about 0.185 m up) but about 0.12 m under the floor at LOW_POSE.
LONG = _tool("probe", 0.3)


@pytest.fixture
def client(sim: SimController) -> Iterator[TestClient]:
    with TestClient(create_app(sim)) as test_client:
        yield test_client


def _tool_json(tool: Tool) -> dict[str, object]:
    return tool.model_dump(mode="json")


@pytest.mark.parametrize("tool", [TOO_LONG, TOO_WIDE], ids=["tip", "radius"])
def test_a_tool_in_the_floor_is_refused_and_the_old_one_kept(sim: SimController, tool: Tool) -> None:
    with pytest.raises(Collision) as info:
        sim.set_tool(tool)
    assert info.value.message == MSG_COLLISION
    assert sim.get_tool() == DEFAULT_TOOL


@pytest.mark.parametrize("tool", [TOO_LONG, TOO_WIDE], ids=["tip", "radius"])
def test_post_tool_in_the_floor_is_412_collision_detected(client: TestClient, tool: Tool) -> None:
    before = client.get("/tool").json()
    response = client.post("/tool", json=_tool_json(tool))
    assert response.status_code == 412
    assert response.json() == MSG_COLLISION
    assert client.get("/tool").json() == before


def test_after_a_refused_tool_the_arm_still_moves(sim: SimController, clock: FakeClock) -> None:
    with pytest.raises(Collision):
        sim.set_tool(TOO_LONG)
    sim.set_pose(NUDGED_HOME, JOINT_50)
    finish(sim, clock)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == pytest.approx(NUDGED_HOME.angles, abs=ANGLE_TOL_DEG)


def test_a_sensible_tool_is_accepted_and_moves_still_work(sim: SimController, clock: FakeClock) -> None:
    assert sim.set_tool(SENSIBLE) == SENSIBLE
    home = Pose(angles=list(HOME_POSE_DEG))
    sim.set_pose(home, JOINT_50)  # stay where you are
    sim.set_position(sim.get_position(), JOINT_50)
    sim.set_pose(NUDGED_HOME, JOINT_50)
    finish(sim, clock)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_pose().angles == pytest.approx(NUDGED_HOME.angles, abs=ANGLE_TOL_DEG)
    assert sim.get_tool() == SENSIBLE


def test_post_tool_sensible_then_put_pose_works(
    client: TestClient, sim: SimController, clock: FakeClock
) -> None:
    response = client.post("/tool", json=_tool_json(SENSIBLE))
    assert response.status_code == 200, response.text
    assert Tool.model_validate(client.get("/tool").json()) == SENSIBLE
    moved = client.put("/pose", params={"speed": 50}, json=NUDGED_HOME.model_dump(mode="json"))
    assert moved.status_code == 200, moved.text
    finish(sim, clock)
    assert client.get("/status/motion").json() == "IDLE"
    assert client.get("/pose").json()["angles"] == pytest.approx(NUDGED_HOME.angles, abs=ANGLE_TOL_DEG)


def test_a_tool_in_the_floor_where_the_queue_ends_is_refused(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(LOW_POSE, JOINT_50)
    with pytest.raises(Collision):
        sim.set_tool(LONG)  # fine where the arm is, not where it is going
    assert sim.get_tool() == DEFAULT_TOOL
    finish(sim, clock)
    assert sim.get_pose().angles == pytest.approx(LOW_POSE.angles, abs=ANGLE_TOL_DEG)
    with pytest.raises(Collision):
        sim.set_tool(LONG)  # and now it is there


def test_a_tool_in_the_floor_where_the_arm_is_is_refused_while_it_moves_away(
    sim: SimController, clock: FakeClock
) -> None:
    sim.set_pose(LOW_POSE, JOINT_50)
    finish(sim, clock)
    sim.set_pose(Pose(angles=list(HOME_POSE_DEG)), JOINT_50)
    with pytest.raises(Collision):
        sim.set_tool(LONG)  # clear at the queue's end, in the floor at the start
    assert sim.get_tool() == DEFAULT_TOOL
    finish(sim, clock)
    assert sim.set_tool(LONG) == LONG


def test_the_floor_rule_is_the_one_moves_use(sim: SimController, clock: FakeClock) -> None:
    """A sphere just clear of the floor is accepted and the arm can still lift it; one just in is refused."""
    height = sim.get_position().point.z  # the bare flange's height at the power-on pose
    with pytest.raises(Collision):
        sim.set_tool(_tool("touching", 0.0, radius=height + FLOOR_MARGIN_M))
    grazing = _tool("grazing", 0.0, radius=height - FLOOR_MARGIN_M)
    assert sim.set_tool(grazing) == grazing
    sim.set_pose(Pose(angles=list(HOME_POSE_DEG)), JOINT_50)  # stay where you are
    start = sim.get_position()
    lifted = start.model_copy(update={"point": start.point.model_copy(update={"z": start.point.z + LIFT_M})})
    sim.set_position(lifted, LINEAR_50)
    finish(sim, clock)
    assert sim.get_motion_status() is MotionStatus.IDLE
    assert sim.get_position().point.z == pytest.approx(start.point.z + LIFT_M, abs=POS_TOL_M)
