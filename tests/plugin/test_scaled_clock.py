"""ScaledClock: simulated time K times the wall clock, stops that hold it for scripted events, and the
simulator on it (a motion's simulated duration is the same at every scale). A fake wall clock: no sleeps."""

from __future__ import annotations

import pytest

from pendant.controller.types import MotionParams, Pose
from pendant.sim import ScaledClock, SimController
from pendant.sim.clock import MAX_TIME_SCALE, MIN_TIME_SCALE

FAR = Pose(angles=[120.0, -90.0, 90.0, -90.0, -90.0, 0.0])


class Wall:
    """A wall clock the test moves."""

    def __init__(self) -> None:
        self.t = 1000.0

    def __call__(self) -> float:
        return self.t


@pytest.fixture
def wall() -> Wall:
    return Wall()


@pytest.mark.parametrize("scale", [MIN_TIME_SCALE, 1.0, 100.0, MAX_TIME_SCALE])
def test_simulated_time_runs_k_times_the_wall(wall: Wall, scale: float) -> None:
    clock = ScaledClock(scale, wall=wall)
    assert clock.now() == 0.0
    wall.t += 2.0
    assert clock.now() == pytest.approx(2.0 * scale)
    assert clock.wall_seconds_until(4.0 * scale) == pytest.approx(2.0)


@pytest.mark.parametrize("scale", [0.0, 0.05, 1000.5, float("nan"), float("inf"), -1.0])
def test_scales_out_of_range_are_refused(scale: float) -> None:
    with pytest.raises(ValueError, match=r"time scale must be between 0\.1 and 1000"):
        ScaledClock(scale)


def test_changing_the_scale_keeps_the_time_read_so_far(wall: Wall) -> None:
    clock = ScaledClock(10.0, wall=wall)
    wall.t += 1.0
    clock.set_scale(100.0)
    assert clock.now() == pytest.approx(10.0)
    wall.t += 1.0
    assert clock.now() == pytest.approx(110.0)


def test_a_stop_holds_time_until_removed_and_time_resumes_from_it(wall: Wall) -> None:
    clock = ScaledClock(10.0, wall=wall)
    clock.add_stop(5.0)
    wall.t += 2.0  # 20 s free-running
    assert clock.now() == 5.0
    clock.remove_stop(5.0)
    assert clock.now() == 5.0  # no jump over the time it was held
    wall.t += 0.5
    assert clock.now() == pytest.approx(10.0)


def test_a_stop_in_the_past_is_refused(wall: Wall) -> None:
    clock = ScaledClock(10.0, wall=wall)
    wall.t += 1.0
    with pytest.raises(ValueError, match="simulated time 5 s has passed"):
        clock.add_stop(5.0)
    assert clock.now() == pytest.approx(10.0)


def test_hold_freezes_the_present(wall: Wall) -> None:
    clock = ScaledClock(100.0, wall=wall)
    wall.t += 0.01
    held = clock.hold()
    wall.t += 1.0
    assert clock.now() == held == pytest.approx(1.0)
    clock.remove_stop(held)
    clock.remove_stop(held)  # already gone: no error
    wall.t += 0.01
    assert clock.now() == pytest.approx(2.0)


def test_timestamps_follow_simulated_time(wall: Wall) -> None:
    clock = ScaledClock(50.0, wall=wall)
    start = clock.unix_time(clock.now())
    wall.t += 3.0
    assert clock.unix_time(clock.now()) - start == pytest.approx(150.0)


@pytest.mark.parametrize("scale", [0.1, 1.0, 100.0])
def test_a_motion_takes_the_same_simulated_time_at_every_scale(wall: Wall, scale: float) -> None:
    clock = ScaledClock(scale, wall=wall)
    sim = SimController(clock=clock)
    sim.set_pose(FAR, MotionParams(speed=10.0))
    duration = sim.busy_until() - clock.now()
    wall.t += 0.999 * duration / scale
    assert sim.get_motion_status() == "RUNNING"
    wall.t += 0.002 * duration / scale
    assert sim.get_motion_status() == "IDLE"
    assert sim.get_pose().angles == pytest.approx(FAR.angles)
    reference = SimController(clock=ScaledClock(1.0, wall=Wall()))
    reference.set_pose(FAR, MotionParams(speed=10.0))
    assert duration == pytest.approx(reference.busy_until(), rel=1e-12)
