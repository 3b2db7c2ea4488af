"""The contact rule on the simulator and the pendant's own checks: an arm caught by a new obstacle can be
backed out of it, never pushed deeper in, never into another obstacle.

The obstacle is the wall of Rozum's SDK README (example 10): the plane x = -0.5 m, which the wrist and the
gripper reach 13 mm into at the simulator's power-on pose.
"""

from __future__ import annotations

import numpy as np
import pytest

from pendant.cell.geometry import CellAwareArm, CellModel
from pendant.controller.cell_types import PlaneObstacle, SimplifiedCapsuleObstacle, ToolShape
from pendant.controller.errors import Collision, PreconditionFailed
from pendant.controller.system_types import JoggingVector
from pendant.controller.types import MotionParams, Point, Pose
from pendant.jog.targets import JogFrame, JogRequest, joint_jog_target
from pendant.kinematics.contact import CONTACT_DEEPER_TOLERANCE_M, worse_contact
from pendant.sim import FakeClock, SimController
from pendant.ui.target.check import check_joint_target
from tests.support.sim_sampling import finish

README_WALL = PlaneObstacle(
    obstacleType="PLANE",
    name="wall",
    points=[Point(x=-0.5, y=0.4, z=0.0), Point(x=-0.5, y=0.0, z=0.0), Point(x=-0.5, y=0.0, z=0.1)],
)
HOME = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # the simulator's power-on pose
DEEPER = [0.0, -90.0, 95.0, -90.0, -90.0, 0.0]  # the forearm tips the gripper further past the wall
OUT = [15.0, -90.0, 90.0, -90.0, -90.0, 0.0]  # turning the base swings the wrist away from it
SPEED = MotionParams(speed=50.0)
DEG_TOL = 1e-6


@pytest.fixture
def clock() -> FakeClock:
    return FakeClock()


@pytest.fixture
def sim(clock: FakeClock) -> SimController:
    return SimController(clock=clock)


def wall_contacts(sim: SimController) -> dict[str | None, float]:
    q = np.radians(sim.get_pose().angles)
    return {name: c.depth_m for name, c in sim.environment.geometry.contacts(q).items()}


def test_the_rule_refuses_a_new_contact_and_a_deeper_one_within_a_named_tolerance() -> None:
    allowed: dict[str | None, float] = {"wall": 0.013}
    assert worse_contact(allowed, {"wall": 0.013 + 0.5 * CONTACT_DEEPER_TOLERANCE_M}) is None
    assert worse_contact(allowed, {"wall": 0.005}) is None  # shallower: backing out
    deeper = worse_contact(allowed, {"wall": 0.013 + 2 * CONTACT_DEEPER_TOLERANCE_M})
    assert deeper is not None and deeper.describe() == "would go deeper into 'wall' (13 mm -> 15 mm)"
    new = worse_contact(allowed, {"wall": 0.010, "post": 0.0})  # a graze of another obstacle is new
    assert new is not None and new.describe() == "would touch 'post'"
    floor = worse_contact({}, {None: 0.002})
    assert floor is not None and floor.describe() == "would touch the floor"


def test_a_wall_touching_the_arm_at_rest_is_taken_and_the_arm_backs_out_of_it(
    sim: SimController, clock: FakeClock
) -> None:
    assert sim.get_pose().angles == HOME
    added = sim.add_obstacle(README_WALL)
    assert added == "Obstacle 'wall' added touching the arm (link5, link6, gripper_body)"
    depth = wall_contacts(sim)["wall"]
    assert 0.005 < depth < 0.03  # the wrist is a centimetre or two into it

    with pytest.raises(Collision, match=r"^Collision detected: the arm would go deeper into 'wall' \("):
        sim.set_pose(Pose(angles=DEEPER), SPEED)
    assert sim.get_pose().angles == HOME  # refused: nothing moved

    sim.set_pose(Pose(angles=OUT), SPEED)
    finish(sim, clock)
    assert sim.get_pose().angles == pytest.approx(OUT, abs=DEG_TOL)
    assert wall_contacts(sim) == {}  # out of contact

    with pytest.raises(Collision, match=r"^Collision detected: the arm would touch 'wall'$"):
        sim.set_pose(Pose(angles=HOME), SPEED)  # once out, going back in is a new contact
    assert sim.get_pose().angles == pytest.approx(OUT, abs=DEG_TOL)


def test_a_jog_backs_out_of_the_wall_and_not_into_it(sim: SimController, clock: FakeClock) -> None:
    sim.add_obstacle(README_WALL)
    with pytest.raises(PreconditionFailed, match="Cannot jog that way"):  # towards -x: deeper at once
        sim.jog(JoggingVector(x=-0.5, y=0.0, z=0.0, rx=0.0, ry=0.0, rz=0.0))
    assert sim.get_pose().angles == HOME
    sim.jog(JoggingVector(x=0.5, y=0.0, z=0.0, rx=0.0, ry=0.0, rz=0.0))  # away from it
    clock.advance(1.0)
    sim.jog(JoggingVector(x=0.0, y=0.0, z=0.0, rx=0.0, ry=0.0, rz=0.0))
    finish(sim, clock)
    assert sim.get_position().point.x > -0.466 + 0.1  # the TCP went 10 cm and more away from the wall
    assert wall_contacts(sim) == {}


def test_the_pendants_jog_and_target_check_apply_the_same_rule(sim: SimController) -> None:
    sim.add_obstacle(README_WALL)
    cell = CellModel(sim.arm, sim.get_obstacles(), ToolShape(shape=[]))
    arm = CellAwareArm(sim.arm, lambda: cell)
    q = np.radians(HOME)
    assert cell.touching(q) == ["wall"]

    def jog(axis: int, direction: int) -> np.ndarray:
        request = JogRequest(JogFrame.JOINT, axis, direction, 50.0, step=np.radians(5.0))
        return joint_jog_target(arm, q, request, joint_speed=1.0)

    assert np.degrees(jog(0, +1)[0]) == pytest.approx(5.0)  # the base turns the wrist out: the full step
    np.testing.assert_allclose(jog(2, +1), q)  # the forearm pushes the gripper in: no progress at all

    out = check_joint_target(sim.arm, np.radians(OUT), cell, q)
    assert out.ok
    deeper = check_joint_target(sim.arm, np.radians(DEEPER), cell, q)
    assert deeper.touching == ("wall",)
    assert deeper.reason is not None and deeper.reason.startswith(
        "Collision detected: the arm would go deeper into 'wall'"
    )


def test_a_hand_may_pull_the_relaxed_arm_out_of_the_wall_not_push_it_in(sim: SimController) -> None:
    sim.add_obstacle(README_WALL)
    sim.relax()
    with pytest.raises(Collision, match="inside 'wall'"):
        sim.move_by_hand(Pose(angles=DEEPER))
    sim.move_by_hand(Pose(angles=OUT))
    assert wall_contacts(sim) == {}


def test_the_tool_may_change_beside_the_wall_but_not_reach_into_it(sim: SimController) -> None:
    sim.add_obstacle(README_WALL)
    short = SimplifiedCapsuleObstacle(radius=0.02, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.05))
    sim.set_tool_shape(ToolShape(shape=[short]))  # inside the gripper's own reach: nothing new touched
    assert sim.get_tool_shape().shape == [short]
    sideways = SimplifiedCapsuleObstacle(  # 20 cm along the flange's -x (the base's -x here): into the wall
        radius=0.02, begin=Point(x=0, y=0, z=0), finish=Point(x=-0.2, y=0, z=0)
    )
    with pytest.raises(Collision, match="tool shape would touch"):
        sim.set_tool_shape(ToolShape(shape=[sideways]))
    assert sim.get_tool_shape().shape == [short]
