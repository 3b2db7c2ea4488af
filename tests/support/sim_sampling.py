"""Sampling helpers for simulator tests: step the fake clock and record what a client would read."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pendant.controller.types import MotionStatus, Point, Position, Rotation
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim import FakeClock, SimController

POS_TOL_M = 1e-6
ANGLE_TOL_DEG = 1e-6
DT = 0.002  # sampling step of recorded trajectories, seconds


@dataclass
class Recording:
    t: np.ndarray  # (n,)
    q_deg: np.ndarray  # (n, 6) poses
    T: np.ndarray  # (n, 4, 4) positions in the zero point frame
    status: list[MotionStatus]

    @property
    def joint_speed_deg_s(self) -> np.ndarray:
        return np.diff(self.q_deg, axis=0) / np.diff(self.t)[:, None]

    @property
    def tcp_speed_m_s(self) -> np.ndarray:
        return np.linalg.norm(np.diff(self.T[:, :3, 3], axis=0), axis=1) / np.diff(self.t)


def record(sim: SimController, clock: FakeClock, dt: float = DT, limit_s: float = 120.0) -> Recording:
    """Sample pose, position and status every dt until the arm is IDLE again (inclusive)."""
    t0 = clock.now()
    ts, qs, Ts, statuses = [], [], [], []
    while True:
        ts.append(clock.now() - t0)
        qs.append(sim.get_pose().angles)
        Ts.append(position_to_matrix(sim.get_position()))
        status = sim.get_motion_status()
        statuses.append(status)
        if status is not MotionStatus.RUNNING:
            break
        if clock.now() - t0 > limit_s:
            raise AssertionError("the arm did not stop")
        clock.advance(dt)
    return Recording(np.array(ts), np.array(qs), np.array(Ts), statuses)


def finish(sim: SimController, clock: FakeClock, step: float = 0.5, limit_s: float = 300.0) -> float:
    """Advance until the arm is no longer RUNNING; returns the time it took (to within `step`)."""
    waited = 0.0
    while sim.get_motion_status() is MotionStatus.RUNNING:
        clock.advance(step)
        waited += step
        assert waited < limit_s, "the arm did not stop"
    return waited


def position(
    x: float, y: float, z: float, roll: float = 0.0, pitch: float = 0.0, yaw: float = 0.0
) -> Position:
    return Position(point=Point(x=x, y=y, z=z), rotation=Rotation(roll=roll, pitch=pitch, yaw=yaw))


def shifted(p: Position, dx: float = 0.0, dy: float = 0.0, dz: float = 0.0) -> Position:
    return Position(point=Point(x=p.point.x + dx, y=p.point.y + dy, z=p.point.z + dz), rotation=p.rotation)


MOTION_SETTLE_S = 0.1  # beyond the end of everything queued


def finish_motion(sim: SimController, clock: FakeClock) -> None:
    clock.advance(sim.busy_until() - clock.now() + MOTION_SETTLE_S)


def pose_deg(sim: SimController) -> np.ndarray:
    """The joint angles, degrees."""
    return np.asarray(sim.get_pose().angles)


def home_q(sim: SimController) -> np.ndarray:
    """The joint angles, radians (as the kinematics take them)."""
    return np.radians(sim.get_pose().angles)
