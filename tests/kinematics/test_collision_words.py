"""One collision, the same words wherever the operator meets it: the simulator's refusal of a move (Go to,
Run), the Target tab's check (the Cell tab's too), and a jog stopped short of it."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.cell.collision_names import explain_collision, name_collision
from pendant.cell.geometry import CellAwareArm, CellModel
from pendant.controller import MotionParams, Point, Pose, Position, Rotation
from pendant.controller.cell_types import BoxObstacle
from pendant.controller.errors import MSG_COLLISION, Collision
from pendant.jog import JogFrame, JogRequest
from pendant.jog.blocked import why_blocked
from pendant.jog.targets import JOINT_SAMPLE_RAD
from pendant.sim import SimController

FOLDED = np.radians([0.0, -90.0, 170.0, 0.0, 0.0, 0.0])  # the forearm folded onto the upper arm


def box(name: str, xyz: np.ndarray) -> BoxObstacle:
    return BoxObstacle(
        obstacleType="BOX",
        name=name,
        sides=Point(x=0.1, y=0.1, z=0.1),
        centerPosition=Position(
            point=Point(x=float(xyz[0]), y=float(xyz[1]), z=float(xyz[2])),
            rotation=Rotation(roll=0, pitch=0, yaw=0),
        ),
    )


def test_a_box_in_the_way_is_named_alike_by_the_controller_the_target_check_and_the_jog(
    sim: SimController,
) -> None:
    home = np.radians(np.asarray(sim.get_pose().angles, dtype=float))
    target = home + np.radians([20.0, 0, 0, 0, 0, 0])
    sim.add_obstacle(box("Box 1", sim.arm.fk(target)[:3, 3]))  # around the flange at the target
    cell = CellModel(sim.arm, sim.get_obstacles(), sim.get_tool_shape(), sim.get_tool())
    words = "Collision detected: the arm would touch 'Box 1'"

    with pytest.raises(Collision) as refused:  # Go to / Run: the controller (simulator) refuses the move
        sim.set_pose(Pose(angles=list(np.degrees(target))), MotionParams(speed=50.0))
    assert refused.value.message == words
    assert name_collision(sim.arm, target, cell).reason == words  # Target / Cell tab
    # A real controller's bare "Collision detected" gets the same words from the page.
    assert explain_collision(MSG_COLLISION, sim.arm, target, cell).reason == words

    # The jog, just short of the box, cannot go further: the same words.
    just_short = home + np.radians([16.0, 0, 0, 0, 0, 0])
    while cell.collides(just_short):
        just_short[0] -= np.radians(1.0)
    arm = CellAwareArm(sim.arm, lambda: cell)
    request = JogRequest(JogFrame.JOINT, 0, +1, 50.0)
    assert why_blocked(arm, just_short, request, cell.touching) == words


def test_the_arm_against_itself_names_its_two_links_in_the_jog_as_in_the_target_check(
    sim: SimController,
) -> None:
    named = name_collision(sim.arm, FOLDED)
    assert named.reason is not None and named.reason.startswith(f"{MSG_COLLISION}: link")
    assert " would touch link" in named.reason
    # The elbow closing onto the folded pose: the jog stops with the same two links named.
    q = FOLDED.copy()
    while sim.arm.in_collision(q):
        q[2] -= JOINT_SAMPLE_RAD
    ahead = q.copy()
    while not sim.arm.in_collision(ahead):
        ahead[2] += JOINT_SAMPLE_RAD
    request = JogRequest(JogFrame.JOINT, 2, +1, 50.0)
    assert why_blocked(sim.arm, q, request, lambda q: []) == name_collision(sim.arm, ahead).reason
