"""The ONE cell check (pendant.kinematics.cell_check): the same answers as the checker it replaced on random
configurations, the margin the planner pads with, distances, and a cell that changes at run time."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck, NamedShape
from pendant.kinematics.cell_shapes import obstacle_shape, tool_capsules
from pendant.kinematics.obstacles import Capsule, box_shape
from pendant.planning.scenes import FLANGE, HOME_DEG, README_CELL, SCENES
from pendant.sim import FakeClock, SimController
from tests.support.reference_cell_check import CellGeometry

CONFIGURATIONS = 10_000
CONTACT_TOL_M = 0.0005  # a disagreement is allowed only this close to contact
MARGIN_M = 0.005
LEVEL = Rotation(roll=0.0, pitch=0.0, yaw=0.0)


@pytest.fixture(scope="module")
def arm() -> ArmModel:
    return ArmModel.load("pulse75")


def test_the_new_check_agrees_with_the_old_on_ten_thousand_random_configurations(arm: ArmModel) -> None:
    """The README's cell (a table, a post, a wall, a tool capsule): the old check (the arm's own pairs, then a
    Python loop over coal pairs) and the new one give the same verdict, but within 0.5 mm of contact."""
    scene = README_CELL
    old = CellGeometry(
        arm, [obstacle_shape(o) for o in scene.obstacles], tool_capsules(scene.tool_shape, FLANGE)
    )
    new = scene.check(arm)
    qs = np.random.default_rng(28).uniform(arm.lower, arm.upper, (CONFIGURATIONS, 6))
    by_cell = np.array([old.collides(q) for q in qs])
    by_arm = np.array([arm.in_collision(q) for q in qs])
    before = by_cell | by_arm
    after = new.collides_many(qs)
    one_by_one = np.array([new.collides(q) for q in qs[:1000]])
    assert np.array_equal(one_by_one, after[:1000])  # a batch answers as single checks do
    assert by_cell.mean() > 0.1 and (~before).mean() > 0.1  # the sample has cell contacts and free space
    disagreeing = qs[before != after]
    distances = [abs(new.clearance(q, with_itself=True).distance_m) for q in disagreeing]
    assert all(d <= CONTACT_TOL_M for d in distances), distances


def _box_beside_the_arm(arm: ArmModel, gap_m: float) -> tuple[CellCheck, np.ndarray]:
    """A 0.1 m box right under the hand at home, its top `gap_m` below the hand's lowest point (found with
    a first box whose top is 0.4 m high: nearer the hand than anything is to the floor)."""
    q = np.radians(HOME_DEG)

    def box_with_top_at(z_top: float) -> CellCheck:
        T = _at(-0.466, -0.121, z_top - 0.05)  # under the TCP
        return CellCheck(arm, [NamedShape("box", *box_shape(np.array([0.1, 0.1, 0.1]), T))])

    first = box_with_top_at(0.4).clearance(q)
    assert first.to == "box"
    return box_with_top_at(0.4 + first.distance_m - gap_m), q


def _at(x: float, y: float, z: float) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


@pytest.mark.parametrize("gap_mm", [3.0, 4.5])
def test_an_obstacle_closer_than_the_margin_counts_as_a_collision_only_when_padded(
    arm: ArmModel, gap_mm: float
) -> None:
    check, q = _box_beside_the_arm(arm, gap_mm / 1e3)
    assert check.clearance(q).distance_m == pytest.approx(gap_mm / 1e3, abs=1e-5)
    assert check.clearance(q).to == "box"
    assert not check.collides(q) and check.touching(q) is None
    padded = check.with_margin(MARGIN_M)
    assert padded.collides(q) and padded.touching(q) == ["box"]
    assert padded.collides_many(np.tile(q, (100, 1))).all()  # the batch is padded too


def test_an_obstacle_beyond_the_margin_is_clear_even_when_padded(arm: ArmModel) -> None:
    check, q = _box_beside_the_arm(arm, 0.006)
    assert not check.with_margin(MARGIN_M).collides(q)


def test_a_penetration_is_a_negative_distance(arm: ArmModel) -> None:
    check, q = _box_beside_the_arm(arm, -0.002)
    assert check.clearance(q).distance_m == pytest.approx(-0.002, abs=1e-4)
    assert check.touching(q) == ["box"]


def test_obstacles_added_and_removed_at_run_time_change_the_simulators_answers() -> None:
    sim = SimController(clock=FakeClock())
    q = sim.joint_positions()
    T_flange = sim.arm.fk(q)
    beside = T_flange[:3, 3] + np.array([0.0, 0.3, 0.0])
    box = BoxObstacle(
        obstacleType="BOX",
        name="crate",
        sides=Point(x=0.1, y=0.1, z=0.1),
        centerPosition=Position(point=Point(x=beside[0], y=beside[1], z=beside[2]), rotation=LEVEL),
    )
    moved = q.copy()
    moved[0] -= np.radians(25.0)  # swings the hand into the crate
    assert sim.environment.touching(moved) is None
    sim.add_obstacle(box)
    assert sim.environment.touching(moved) == ["crate"]
    sim.remove_obstacle("crate")
    assert sim.environment.touching(moved) is None
    on_the_hand = box.model_copy(
        update={
            "centerPosition": Position(
                point=Point(x=T_flange[0, 3], y=T_flange[1, 3], z=T_flange[2, 3]), rotation=LEVEL
            )
        }
    )
    # Touching the arm where it stands still: taken, as a controller takes it (the contact rule then lets
    # the arm only back out of it; tests/sim/test_contact.py), and the answer says which links it touches.
    assert sim.add_obstacle(on_the_hand).startswith("Obstacle 'crate' added touching the arm (")
    contact = sim.environment.geometry.contacts(q)["crate"]
    assert contact.depth_m > 0.01 and "link6" in contact.links


@pytest.mark.parametrize("scene", SCENES, ids=[s.name for s in SCENES])
def test_every_scene_starts_clear_and_its_straight_path_is_blocked(arm: ArmModel, scene: object) -> None:
    from pendant.planning.scenes import Scene

    assert isinstance(scene, Scene)
    check = scene.check(arm).with_margin(MARGIN_M)
    start, target = np.radians(scene.start_deg), np.radians(scene.target_deg)
    assert not check.collides(start) and not check.collides(target)
    assert check.path_collides(start, target, np.radians(1.0))


def test_a_tool_capsule_ending_inside_a_box_is_a_collision(arm: ArmModel) -> None:
    """A capsule whose end is at a box's centre: coal's GJK without contacts answered "clear" here."""
    q = np.radians(HOME_DEG)
    flange = arm.fk(q)
    T = _at(*(flange[:3, 3] + 0.15 * flange[:3, 2]))
    box = NamedShape("box", *box_shape(np.array([0.04, 0.04, 0.04]), T))
    tool = [Capsule(0.03, np.zeros(3), np.array([0.0, 0.0, 0.15]))]
    check = CellCheck(arm, [box], tool)
    assert check.touching(q) == ["box"]
    assert check.collides(q) and check.collides_many(np.tile(q, (100, 1))).all()
