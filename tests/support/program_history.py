"""Programs for the history tests: waypoints placed by hand (millimetres), so a move has a known distance."""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

from pendant.controller.types import Point, Pose, Position, Rotation
from pendant.program import LoopStep, MoveStep, Program, Step, WaitStep, Waypoint

HOME_DEG = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]


def waypoint(
    name: str, x_mm: float, y_mm: float = 0.0, z_mm: float = 300.0, yaw_deg: float = 0.0
) -> Waypoint:
    return Waypoint(
        name=name,
        pose=Pose(angles=list(HOME_DEG)),
        position=Position(
            point=Point(x=x_mm / 1000, y=y_mm / 1000, z=z_mm / 1000),
            rotation=Rotation(roll=math.pi, pitch=0.0, yaw=math.radians(yaw_deg)),
        ),
    )


def pick_program(*, speed: float = 20.0, loop_times: int = 3, extra: tuple[Step, ...] = ()) -> Program:
    """P1, P2, P3 and five steps: moves to each, a loop of one wait."""
    return Program(
        name="pick",
        waypoints=(waypoint("P1", 400.0), waypoint("P2", 450.0), waypoint("P3", 500.0)),
        steps=(
            MoveStep(waypoint="P1", speed=speed),
            MoveStep(waypoint="P2"),
            MoveStep(waypoint="P3"),
            LoopStep(times=loop_times, body=(WaitStep(ms=500),)),
            *extra,
        ),
    )


def git(folder: Path, *args: str) -> str:
    """The `git` binary's answer in `folder` (it must agree with what dulwich wrote)."""
    done = subprocess.run(
        ["git", "-C", str(folder), *args], capture_output=True, text=True, timeout=30, check=True
    )
    return done.stdout


def cut_head_commit(folder: Path) -> None:
    """Cut the HEAD commit's object file in half, as a disk or a copy interrupted mid-way leaves it."""
    head = git(folder, "rev-parse", "HEAD").strip()
    path = folder / ".git" / "objects" / head[:2] / head[2:]
    data = path.read_bytes()
    path.chmod(0o644)
    path.write_bytes(data[: len(data) // 2])
