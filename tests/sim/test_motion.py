"""JOINT and LINEAR motions as a client sees them: where the arm goes, how fast, and in what order."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.types import MotionParams, MotionStatus, MotionType, Pose
from pendant.kinematics.limits import JOINT_MAX_ACCEL_RAD_S2, JOINT_MAX_SPEED_RAD_S
from pendant.kinematics.transforms import matrix_to_rotvec, rotation_angle, rotvec_to_matrix
from pendant.sim import FakeClock, SimController
from pendant.sim.paths import CARTESIAN_BLEND_TOL_M
from tests.support.sim_sampling import ANGLE_TOL_DEG, DT, POS_TOL_M, finish, record, shifted

LINE_TOL_M = 1e-4  # a LINEAR path stays this close to its line
SPEED_TOL = 1e-6  # relative slack on measured peak speeds (finite differences of an exact profile)
TARGET = Pose(angles=[40.0, -70.0, 60.0, -100.0, -60.0, 30.0])
JOINT_50 = MotionParams(speed=50)


def test_joint_motion_ends_exactly_at_the_target(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    rec = record(sim, clock)
    assert rec.status[-1] is MotionStatus.IDLE
    assert np.allclose(sim.get_pose().angles, TARGET.angles, atol=ANGLE_TOL_DEG)


def test_joint_motion_moves_all_joints_in_step(sim: SimController, clock: FakeClock) -> None:
    start = np.array(sim.get_pose().angles)
    sim.set_pose(TARGET, JOINT_50)
    rec = record(sim, clock)
    progress = (rec.q_deg - start) / (np.array(TARGET.angles) - start)
    # Every joint is the same fraction of the way at every instant: they start and end together.
    assert np.allclose(progress, progress[:, :1], atol=1e-9)
    moving = np.any(np.abs(rec.joint_speed_deg_s) > 1e-9, axis=1)
    assert moving[0] and moving[-1]


@pytest.mark.parametrize("speed", [10.0, 50.0, 100.0])
def test_joint_speed_stays_within_speed_percent_of_the_limits(
    sim: SimController, clock: FakeClock, speed: float
) -> None:
    sim.set_pose(Pose(angles=[170.0, -100.0, 100.0, -30.0, -150.0, 120.0]), MotionParams(speed=speed))
    rec = record(sim, clock, dt=0.001)
    limit = np.degrees(JOINT_MAX_SPEED_RAD_S) * speed / 100.0
    peak = np.max(np.abs(rec.joint_speed_deg_s), axis=0)
    assert np.all(peak <= limit * (1 + SPEED_TOL))
    assert np.max(peak / limit) > 0.99  # and the leading joint does reach its limit on a long move
    accel = np.diff(rec.joint_speed_deg_s, axis=0) / 0.001
    # Finite differences smear the corners of the velocity profile; half a percent covers that.
    assert np.all(np.max(np.abs(accel), axis=0) <= np.degrees(JOINT_MAX_ACCEL_RAD_S2) * speed / 100 * 1.005)


def test_lower_acceleration_takes_longer(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, MotionParams(speed=100))
    fast = finish(sim, clock, step=0.01)
    sim.set_pose(Pose(angles=list(np.array(TARGET.angles) - 30.0)), MotionParams(speed=100))
    finish(sim, clock, step=0.01)
    sim.set_pose(TARGET, MotionParams(speed=100, acceleration=10))
    assert finish(sim, clock, step=0.01) > fast + 0.5


def test_linear_motion_stays_on_the_line_and_slerps_orientation(sim: SimController, clock: FakeClock) -> None:
    start = sim.get_position()
    target = shifted(start, dx=-0.15, dy=0.2, dz=-0.1)
    target = type(target)(
        point=target.point,
        rotation=type(start.rotation)(
            roll=start.rotation.roll - 0.4, pitch=start.rotation.pitch + 0.3, yaw=start.rotation.yaw + 0.5
        ),
    )
    sim.set_position(target, MotionParams(speed=60, motion_type=MotionType.LINEAR))
    rec = record(sim, clock, dt=0.001)
    p0 = np.array([start.point.x, start.point.y, start.point.z])
    p1 = np.array([target.point.x, target.point.y, target.point.z])
    direction = (p1 - p0) / np.linalg.norm(p1 - p0)
    offsets = rec.T[:, :3, 3] - p0
    along = offsets @ direction
    off_line = np.linalg.norm(offsets - np.outer(along, direction), axis=1)
    assert np.max(off_line) < LINE_TOL_M
    assert np.allclose(rec.T[-1, :3, 3], p1, atol=POS_TOL_M)
    # Orientation: the turn from the start is the same fraction of the whole turn as the distance travelled.
    R0, R1 = rec.T[0, :3, :3], rec.T[-1, :3, :3]
    turn = matrix_to_rotvec(R1 @ R0.T)
    for T, u in zip(rec.T[::25], along[::25] / np.linalg.norm(p1 - p0), strict=True):
        assert rotation_angle(T[:3, :3], rotvec_to_matrix(turn * u) @ R0) < 1e-3


@pytest.mark.parametrize("motion_type", [MotionType.JOINT, MotionType.LINEAR])
def test_tcp_max_velocity_caps_the_tcp_speed(
    sim: SimController, clock: FakeClock, motion_type: MotionType
) -> None:
    start = sim.get_position()
    cap = 0.1
    sim.set_position(
        shifted(start, dx=-0.2, dy=0.3),
        MotionParams(speed=100, motion_type=motion_type, tcp_max_velocity=cap),
    )
    rec = record(sim, clock, dt=0.001)
    assert np.max(rec.tcp_speed_m_s) <= cap * (1 + 1e-3)
    assert np.max(rec.tcp_speed_m_s) > 0.9 * cap  # the cap, not the joints, set the pace


def test_poses_run_passes_waypoints_without_stopping(sim: SimController, clock: FakeClock) -> None:
    via = Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, 10.0])
    end = Pose(angles=[40.0, -60.0, 60.0, -100.0, -90.0, 30.0])
    sim.run_poses([via, end], JOINT_50)
    rec = record(sim, clock, dt=0.001)
    k = int(np.argmin(np.max(np.abs(rec.q_deg - via.angles), axis=1)))
    # The 1 ms samples straddle the waypoint: the nearest is within one sample's travel of it.
    speed = np.max(np.abs(rec.joint_speed_deg_s[k]))
    assert np.max(np.abs(rec.q_deg[k] - via.angles)) <= speed * 0.001
    assert speed > 10.0  # still moving at the waypoint
    assert np.allclose(rec.q_deg[-1], end.angles, atol=ANGLE_TOL_DEG)
    blended_time = rec.t[-1]
    # The same waypoints as separate PUT /pose commands take longer: the arm stops at each.
    sim.set_pose(Pose(angles=list(rec.q_deg[0])), JOINT_50)
    finish(sim, clock)
    sim.set_pose(via, JOINT_50)
    sim.set_pose(end, JOINT_50)
    assert record(sim, clock).t[-1] > blended_time


def test_separate_pose_commands_stop_at_each_target(sim: SimController, clock: FakeClock) -> None:
    via = Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, 10.0])
    sim.set_pose(via, JOINT_50)
    first_duration = sim.motions.queue[0].duration  # the planned length of the first command
    sim.set_pose(TARGET, JOINT_50)
    clock.advance(first_duration)
    assert np.allclose(sim.get_pose().angles, via.angles, atol=ANGLE_TOL_DEG)
    before = np.array(sim.get_pose().angles)
    clock.advance(DT)
    after = np.array(sim.get_pose().angles)
    # Starting from rest: after DT the move has covered only a = limit * speed * DT^2 / 2.
    assert np.max(np.abs(after - before)) < np.max(np.degrees(JOINT_MAX_ACCEL_RAD_S2)) * DT**2
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, TARGET.angles, atol=ANGLE_TOL_DEG)


def test_positions_run_linear_rounds_corners_within_a_millimetre(
    sim: SimController, clock: FakeClock
) -> None:
    start = sim.get_position()
    corner = shifted(start, dx=-0.15)
    end = shifted(corner, dy=0.15)
    sim.run_positions([corner, end], MotionParams(speed=50, motion_type=MotionType.LINEAR))
    rec = record(sim, clock, dt=0.001)
    p_corner = np.array([corner.point.x, corner.point.y, corner.point.z])
    distances = np.linalg.norm(rec.T[:, :3, 3] - p_corner, axis=1)
    k = int(np.argmin(distances))
    assert distances[k] <= CARTESIAN_BLEND_TOL_M + 1e-5
    assert rec.tcp_speed_m_s[k] > 0.005
    assert np.allclose(rec.T[-1, :3, 3], [end.point.x, end.point.y, end.point.z], atol=POS_TOL_M)


def test_commands_sent_while_moving_run_in_order(sim: SimController, clock: FakeClock) -> None:
    first = Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, 10.0])
    sim.set_pose(first, JOINT_50)
    sim.close_gripper(400)
    sim.set_pose(TARGET, JOINT_50)
    gripper_while_at_first = []
    while sim.get_motion_status() is MotionStatus.RUNNING:
        if np.allclose(sim.get_pose().angles, first.angles, atol=ANGLE_TOL_DEG):
            gripper_while_at_first.append(sim.gripper_opening())
        else:  # moving: the gripper is either still open (before) or already closed (after)
            assert sim.gripper_opening() in (0.0, 1.0)
        clock.advance(0.05)
    # The arm waited at `first` while the gripper closed, then went on to the target.
    assert len(gripper_while_at_first) >= 6 and gripper_while_at_first == sorted(
        gripper_while_at_first, reverse=True
    )
    assert sim.gripper_opening() == 0.0
    assert np.allclose(sim.get_pose().angles, TARGET.angles, atol=ANGLE_TOL_DEG)


def test_a_queued_command_is_checked_from_where_the_queue_ends(sim: SimController, clock: FakeClock) -> None:
    # The flange turned a whole turn further: from home, IK would pick the equivalent angle 10 degrees.
    flipped = Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, -350.0])
    sim.set_pose(flipped, JOINT_50)
    flipped_position = sim.frames.T_zero_origbase @ sim.arm.fk(np.radians(flipped.angles))
    from pendant.kinematics.transforms import matrix_to_position

    sim.set_position(matrix_to_position(flipped_position), JOINT_50)
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, flipped.angles, atol=1e-6)


def test_freeze_stops_the_arm_where_it_is_and_empties_the_queue(sim: SimController, clock: FakeClock) -> None:
    sim.set_pose(TARGET, JOINT_50)
    sim.set_pose(Pose(angles=[0.0, -90.0, 90.0, -90.0, -90.0, 0.0]), JOINT_50)
    clock.advance(0.4)
    frozen_at = sim.get_pose()
    sim.freeze()
    assert sim.get_motion_status() is MotionStatus.IDLE
    clock.advance(30.0)
    assert sim.get_pose() == frozen_at
    assert sim.get_motion_status() is MotionStatus.IDLE
    sim.set_pose(TARGET, JOINT_50)  # the next command starts from the frozen pose
    clock.advance(0.001)
    assert np.max(np.abs(np.array(sim.get_pose().angles) - frozen_at.angles)) < 0.01
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, TARGET.angles, atol=ANGLE_TOL_DEG)


def test_set_position_answers_where_the_arm_is_now(sim: SimController, clock: FakeClock) -> None:
    here = sim.get_position()
    answer = sim.set_position(shifted(here, dz=-0.1), JOINT_50)
    assert answer == here
    finish(sim, clock)
    assert sim.get_position().point.z == pytest.approx(here.point.z - 0.1, abs=POS_TOL_M)


def test_pack_moves_to_the_transport_pose(sim: SimController, clock: FakeClock) -> None:
    from pendant.sim import PACK_POSE_DEG

    sim.pack()
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish(sim, clock)
    assert np.allclose(sim.get_pose().angles, PACK_POSE_DEG, atol=ANGLE_TOL_DEG)


def test_pulse90_moves_too(sim90: SimController, clock: FakeClock) -> None:
    sim90.set_pose(TARGET, JOINT_50)
    finish(sim90, clock)
    assert np.allclose(sim90.get_pose().angles, TARGET.angles, atol=ANGLE_TOL_DEG)


def test_pack_with_no_clear_way_fails_as_a_motion(sim: SimController, clock: FakeClock) -> None:
    # Put by hand into a tangle: every way to the folded pose runs the arm into itself or the floor.
    sim.relax()
    sim.move_by_hand(Pose(angles=[-68.0, -122.0, 140.0, 156.0, -51.0, 26.0]))
    sim.set_pose(Pose(angles=[-60.0, -122.0, 140.0, 156.0, -51.0, 26.0]), JOINT_50)
    sim.pack()  # accepted: the reference lists no 412 for PUT /pack
    sim.set_pose(Pose(angles=[-68.0, -122.0, 140.0, 156.0, -51.0, 26.0]), JOINT_50)
    assert sim.get_motion_status() is MotionStatus.RUNNING
    finish(sim, clock)
    # The first move ran; the pack failed where its turn came and dropped the move queued after it.
    assert sim.get_motion_status() is MotionStatus.MOTION_FAILED
    assert np.allclose(sim.get_pose().angles, [-60.0, -122.0, 140.0, 156.0, -51.0, 26.0], atol=ANGLE_TOL_DEG)
