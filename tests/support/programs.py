"""Programs built in tests: waypoints taught by moving the simulator on its fake clock, and programs of
moves to them (the waypoint table filled from the moves); the runner's commands written down, a sleep
that acts at a given time."""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from pendant.controller import MotionParams, MotionType, Pose
from pendant.program import MoveStep, Program, ProgramRunner, Step, Waypoint
from pendant.program.limits import WAYPOINT_NAME_MAX
from pendant.sim import FakeClock, SimController

# Three poses near home (0, -90, 90, -90, -90, 0), clear of the floor and of each other.
POSE_A_DEG = (20.0, -90.0, 90.0, -90.0, -90.0, 0.0)
POSE_B_DEG = (-20.0, -80.0, 80.0, -90.0, -90.0, 0.0)
POSE_C_DEG = (0.0, -100.0, 100.0, -90.0, -90.0, 10.0)
TEACH_SPEED_PERCENT = 100.0
POLL_S = 0.05
ANGLE_TOL_DEG = 1e-6


def settle(sim: SimController, clock: FakeClock) -> None:
    """Advance the fake clock until everything the simulator has queued is done."""
    clock.advance(max(0.0, sim.busy_until() - clock.now()))


def teach(sim: SimController, clock: FakeClock, angles_deg: tuple[float, ...], name: str) -> Waypoint:
    """Move the simulator to `angles_deg` and read back its pose and TCP position, as Record does."""
    sim.set_pose(Pose(angles=list(angles_deg)), MotionParams(speed=TEACH_SPEED_PERCENT))
    settle(sim, clock)
    return Waypoint(name=name, pose=sim.get_pose(), position=sim.get_position())


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


def many_moves(template: Waypoint, count: int, name: str = "untitled") -> Program:
    """`count` moves with the longest names, each to its own waypoint, alternating JOINT and LINEAR: the
    biggest program to save."""
    moves = [
        move(
            template.model_copy(update={"name": f"{i:0{WAYPOINT_NAME_MAX}d}"}),
            MotionType.LINEAR if i % 2 else MotionType.JOINT,
            speed=33.3333333333,
        )
        for i in range(count)
    ]
    return program_of(*moves, name=name)


class Recording:
    """The simulator, with every command the runner sends written down in order."""

    def __init__(self, sim: SimController) -> None:
        self._sim = sim
        self.calls: list[tuple[str, tuple[Any, ...]]] = []
        self._instead: dict[str, Callable[..., object]] = {}

    def answer(self, name: str, instead: Callable[..., object]) -> None:
        """Call `instead` for the command `name` (not written down): a test's look at the arm mid-program."""
        self._instead[name] = instead

    def __getattr__(self, name: str) -> Any:  # the simulator's: a Controller to the type checker
        if name in self._instead:
            return self._instead[name]
        attribute = getattr(self._sim, name)
        if name.startswith("get_") or not callable(attribute):
            return attribute

        def record(*args: object) -> object:
            self.calls.append((name, args))
            return attribute(*args)

        return record

    def names(self) -> list[str]:
        return [name for name, _ in self.calls]


def sleeping(clock: FakeClock, at: float, action: Callable[[], None]) -> Callable[[float], None]:
    """A sleep that advances the fake clock and does `action` once, when the clock passes `at` seconds."""
    done = False

    def sleep(dt: float) -> None:
        nonlocal done
        clock.advance(dt)
        if not done and clock.now() >= at:
            done = True
            action()

    return sleep


def angles(sim: SimController) -> np.ndarray:
    return np.array(sim.get_pose().angles)


def a_to_b_file(
    name: str, a_deg: list[float], b_deg: list[float], *middle: dict[str, object]
) -> dict[str, object]:
    """A program file's JSON as the pendant saves it: Move J to A, the `middle` steps, Move J to B (100 %)."""
    origin = {"point": {"x": 0.0, "y": 0.0, "z": 0.0}, "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}}
    move_to = [{"kind": "move", "waypoint": w, "motion": "JOINT", "speed": 100.0} for w in ("A", "B")]
    return {
        "schema_version": 2,
        "name": name,
        "waypoints": [
            {"name": "A", "pose": {"angles": a_deg}, "position": origin},
            {"name": "B", "pose": {"angles": b_deg}, "position": origin},
        ],
        "steps": [move_to[0], *middle, move_to[1]],
    }


def runner_doing_at_step(
    sim: SimController, clock: FakeClock, line: int, act: Callable[[ProgramRunner], None]
) -> ProgramRunner:
    """A runner on the fake clock that calls `act(runner)` at each of its sleeps while at step `line`."""
    holder: list[ProgramRunner] = []

    def sleep(dt: float) -> None:
        clock.advance(dt)
        if holder[0].progress.step_index == line:
            act(holder[0])

    runner = ProgramRunner(sim, now=clock.now, sleep=sleep, poll_s=POLL_S)
    holder.append(runner)
    return runner


def swings_file(passes: int) -> dict[str, object]:
    """A program file's JSON: Loop `passes` x (Move J to a, Move J to b): 2 * passes + 1 steps, within the
    pre-flight's step budget for 5,000 passes, but minutes of checking on the twin."""
    origin = {"point": {"x": 0.0, "y": 0.0, "z": 0.0}, "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}}
    waypoints = [
        {"name": name, "pose": {"angles": [j1, -90, 90, -90, -90, 0]}, "position": origin}
        for name, j1 in (("a", 40), ("b", -40))
    ]
    moves = [{"kind": "move", "waypoint": name, "motion": "JOINT", "speed": 100.0} for name in ("a", "b")]
    return {
        "schema_version": 2,
        "name": "swings",
        "waypoints": waypoints,
        "steps": [{"kind": "loop", "mode": "times", "times": passes, "body": moves}],
    }


def dense_program_bytes(steps: int = 170_000) -> bytes:
    """A program file of `steps` small Wait steps (170,000: 4.9 MB, under the 5 MB an upload may have, and
    refused: at most 2,000 steps), the biggest pile of objects a file that size can make its reader build."""
    document = {
        "schema_version": 2,
        "name": "dense",
        "steps": [{"kind": "wait", "ms": i % 1000} for i in range(steps)],
    }
    return json.dumps(document).encode()
