"""Program fixtures: a runner on the simulator's fake clock, and waypoints taught by moving the simulator."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import pytest

from pendant.controller import MotionParams, MotionType, Pose
from pendant.program import MoveStep, Program, ProgramRunner, ProgramStore, ProgramWorkspace, Step, Waypoint
from pendant.sim import FakeClock, SimController

# Three poses near home (0, -90, 90, -90, -90, 0), clear of the floor and of each other.
POSE_A_DEG = (20.0, -90.0, 90.0, -90.0, -90.0, 0.0)
POSE_B_DEG = (-20.0, -80.0, 80.0, -90.0, -90.0, 0.0)
POSE_C_DEG = (0.0, -100.0, 100.0, -90.0, -90.0, 10.0)
TEACH_SPEED_PERCENT = 100.0
POLL_S = 0.05


def settle(sim: SimController, clock: FakeClock) -> None:
    """Advance the fake clock until everything the simulator has queued is done."""
    clock.advance(max(0.0, sim.busy_until() - clock.now()))


def teach(sim: SimController, clock: FakeClock, angles_deg: tuple[float, ...], name: str) -> Waypoint:
    """Move the simulator to `angles_deg` and read back its pose and TCP position, as Record does."""
    sim.set_pose(Pose(angles=list(angles_deg)), MotionParams(speed=TEACH_SPEED_PERCENT))
    settle(sim, clock)
    return Waypoint(name=name, pose=sim.get_pose(), position=sim.get_position())


@pytest.fixture
def waypoints(sim: SimController, clock: FakeClock) -> dict[str, Waypoint]:
    """Waypoints A, B, C taught on the simulator, which is then back at its power-on state."""
    taught = {
        name: teach(sim, clock, pose, name)
        for name, pose in (("A", POSE_A_DEG), ("B", POSE_B_DEG), ("C", POSE_C_DEG))
    }
    sim.reset()
    return taught


@pytest.fixture
def runner(sim: SimController, clock: FakeClock) -> ProgramRunner:
    """A runner whose sleeps advance the fake clock: a whole program runs in milliseconds."""
    return ProgramRunner(sim, sleep=clock.advance, now=clock.now, poll_s=POLL_S)


@pytest.fixture
def make_workspace(tmp_path: Path, runner: ProgramRunner) -> Callable[[], ProgramWorkspace]:
    """A workspace on a programs folder in tmp_path; call again to simulate a restart of the pendant."""
    return lambda: ProgramWorkspace(ProgramStore(tmp_path / "programs"), runner)


class Taught(NamedTuple):
    """A move together with the waypoint it goes to, for `program_of` to put in the waypoint table."""

    waypoint: Waypoint
    step: MoveStep


def move(
    waypoint: Waypoint, motion: MotionType = MotionType.JOINT, speed: float = 50.0, **more: Any
) -> Taught:
    return Taught(waypoint, MoveStep(waypoint=waypoint.name, motion=motion, speed=speed, **more))


def program_of(*items: Step | Taught, name: str = "untitled", extra: tuple[Waypoint, ...] = ()) -> Program:
    """A program of these steps; the waypoints the moves go to (and `extra` ones) make up its table."""
    table: dict[str, Waypoint] = {w.name: w for w in extra}
    steps: list[Step] = []
    for item in items:
        if isinstance(item, Taught):
            table.setdefault(item.waypoint.name, item.waypoint)
            steps.append(item.step)
        else:
            steps.append(item)
    return Program(name=name, waypoints=tuple(table.values()), steps=tuple(steps))
