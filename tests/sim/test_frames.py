"""Tool and zero point: what GET /position reports and what PUT /position means, consistently."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.controller.types import MotionParams, MotionType, Point, Position, Rotation, Tool
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim import DEFAULT_BASE, DEFAULT_TOOL, FakeClock, SimController
from tests.support.sim_sampling import POS_TOL_M, finish, position, record, shifted

ROT_TOL_RAD = 1e-6
LINE_TOL_M = 1e-4
JOINT_50 = MotionParams(speed=50)
GRIPPER = Tool(
    name="gripper",
    point=Point(x=0.0, y=0.02, z=0.15),
    rotation=Rotation(roll=0.0, pitch=0.0, yaw=math.pi / 4),
    radius=0.04,
)


def _xyz(p: Position) -> np.ndarray:
    return np.array([p.point.x, p.point.y, p.point.z])


def _same_place(a: Position, b: Position) -> bool:
    Ta, Tb = position_to_matrix(a), position_to_matrix(b)
    return bool(np.allclose(Ta, Tb, atol=POS_TOL_M))


def test_defaults_are_the_bare_flange_and_the_physical_base(sim: SimController) -> None:
    assert sim.get_tool() == DEFAULT_TOOL
    assert DEFAULT_TOOL.name == "flange" and DEFAULT_TOOL.radius == 0.0
    assert sim.get_base() == DEFAULT_BASE


def test_set_tool_and_set_base_answer_what_they_set(sim: SimController) -> None:
    assert sim.set_tool(GRIPPER) == GRIPPER
    assert sim.get_tool() == GRIPPER
    base = position(0.1, -0.2, 0.05, yaw=0.3)
    assert sim.set_base(base) == base
    assert sim.get_base() == base


def test_a_tool_moves_the_reported_tcp_along_the_flange_axes(sim: SimController) -> None:
    flange = position_to_matrix(sim.get_position())
    sim.set_tool(GRIPPER)
    tcp = position_to_matrix(sim.get_position())
    expected = flange @ position_to_matrix(GRIPPER.position)
    assert np.allclose(tcp, expected, atol=POS_TOL_M)
    # At home the flange points straight down: 15 cm of tool length is 15 cm lower.
    assert tcp[2, 3] == pytest.approx(flange[2, 3] - 0.15, abs=POS_TOL_M)


def test_a_zero_point_offset_shifts_and_turns_the_reported_position(sim: SimController) -> None:
    before = _xyz(sim.get_position())
    sim.set_base(position(0.1, 0.0, 0.2))
    assert np.allclose(_xyz(sim.get_position()), before - [0.1, 0.0, 0.2], atol=POS_TOL_M)
    sim.set_base(position(0.0, 0.0, 0.0, yaw=math.pi / 2))
    # Coordinates in a frame turned +90 degrees about z: x' = y, y' = -x.
    assert np.allclose(_xyz(sim.get_position()), [before[1], -before[0], before[2]], atol=POS_TOL_M)


@pytest.mark.parametrize("motion_type", [MotionType.JOINT, MotionType.LINEAR])
def test_set_position_to_get_position_does_not_move(
    sim: SimController, clock: FakeClock, motion_type: MotionType
) -> None:
    sim.set_tool(GRIPPER)
    sim.set_base(position(0.3, -0.1, 0.1, roll=0.1, pitch=-0.2, yaw=1.0))
    pose = sim.get_pose()
    sim.set_position(sim.get_position(), MotionParams(speed=50, motion_type=motion_type))
    clock.advance(0.001)
    assert np.allclose(sim.get_pose().angles, pose.angles, atol=1e-9)
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, pose.angles, atol=1e-9)


@pytest.mark.parametrize("motion_type", [MotionType.JOINT, MotionType.LINEAR])
def test_set_position_reaches_its_target_in_the_tool_and_base_frames(
    sim: SimController, clock: FakeClock, motion_type: MotionType
) -> None:
    sim.set_tool(GRIPPER)
    sim.set_base(position(0.3, -0.1, 0.1, yaw=1.0))
    target = shifted(sim.get_position(), dx=0.1, dy=-0.05, dz=0.05)
    sim.set_position(target, MotionParams(speed=50, motion_type=motion_type))
    finish(sim, clock)
    assert _same_place(sim.get_position(), target)


def test_a_linear_move_keeps_the_tool_tip_on_the_line(sim: SimController, clock: FakeClock) -> None:
    sim.set_tool(GRIPPER)
    start = sim.get_position()
    target = Position(
        point=shifted(start, dx=-0.1, dy=0.1).point,
        rotation=Rotation(roll=start.rotation.roll, pitch=start.rotation.pitch + 0.4, yaw=start.rotation.yaw),
    )
    sim.set_position(target, MotionParams(speed=50, motion_type=MotionType.LINEAR))
    rec = record(sim, clock, dt=0.002)
    p0, p1 = _xyz(start), _xyz(target)
    direction = (p1 - p0) / np.linalg.norm(p1 - p0)
    offsets = rec.T[:, :3, 3] - p0
    off_line = np.linalg.norm(offsets - np.outer(offsets @ direction, direction), axis=1)
    assert np.max(off_line) < LINE_TOL_M
