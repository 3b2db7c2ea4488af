"""Pre-flight benchmarks: how long checking a program takes, and how close its cycle time is to a run.

Prints
- the wall time of a pre-flight of a ~60 s program (a pallet inside a loop, moves J and L, gripper, waits)
  in a cell of three obstacles (clearance computed), median of 3;
- for every example program: the cycle time the pre-flight predicts against the simulator's own run of it
  in real time (the runner polling the embedded simulator, timed on the simulator's clock), total and the
  largest per-step difference; and against a run on the wall clock, which also counts the simulator's
  planning (`pendant run`'s clock).

    PYTHONPATH=. .venv/bin/python benchmarks/preflight.py
"""

from __future__ import annotations

import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks._timing import wall_times_s
from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import MotionParams, MotionType, Pose, SignalLevel
from pendant.planning.preflight import preflight
from pendant.planning.report import PreflightReport
from pendant.planning.twin import read_seed
from pendant.program import ProgramRunner, RunProgress, RunState
from pendant.program.files import parse_program
from pendant.program.models import (
    GripperAction,
    GripperStep,
    LoopStep,
    MoveStep,
    Offset,
    OutputStep,
    PalletStep,
    Program,
    WaitStep,
    Waypoint,
)
from pendant.sim import FakeClock, MonotonicClock, ScaledClock, SimController

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
REPEATS = 3


def teach(angles: list[tuple[float, ...]]) -> tuple[Waypoint, ...]:
    clock = FakeClock()
    sim = SimController(clock=clock)
    taught = []
    for k, pose in enumerate(angles):
        sim.set_pose(Pose(angles=list(pose)), MotionParams(speed=100.0))
        clock.advance(max(0.0, sim.busy_until() - clock.now()) + 0.1)
        taught.append(Waypoint(name=f"P{k + 1}", pose=sim.get_pose(), position=sim.get_position()))
    return tuple(taught)


POINTS = teach(
    [
        (30.0, -90.0, 90.0, -90.0, -90.0, 0.0),
        (-30.0, -90.0, 90.0, -90.0, -90.0, 0.0),
        (0.0, -80.0, 100.0, -110.0, -90.0, 0.0),
        (10.0, -80.0, 100.0, -110.0, -90.0, 0.0),
        (0.0, -70.0, 100.0, -110.0, -90.0, 0.0),
    ]
)
UP = Offset(z=50.0)


def programs() -> dict[str, Program]:
    pick = parse_program((EXAMPLES / "pick_and_place.json").read_bytes(), "pick_and_place.json")
    linear = Program(
        name="linear",
        waypoints=POINTS,
        steps=(
            MoveStep(waypoint="P3", speed=40.0),
            MoveStep(waypoint="P3", motion=MotionType.LINEAR, offset=UP, speed=30.0),
            MoveStep(waypoint="P4", motion=MotionType.LINEAR, speed=30.0),
            OutputStep(port=1, level=SignalLevel.HIGH),
            MoveStep(waypoint="P5", motion=MotionType.LINEAR, speed=30.0),
        ),
    )
    blended = Program(
        name="blended",
        waypoints=POINTS,
        steps=tuple(MoveStep(waypoint=f"P{k}", speed=50.0, blend_mm=20.0) for k in (1, 2, 3, 1)),
    )
    pallet = Program(
        name="pallet",
        waypoints=POINTS,
        steps=(
            MoveStep(waypoint="P3", speed=50.0),
            PalletStep(
                corners=("P3", "P4", "P5"),
                rows=2,
                columns=2,
                approach_mm=60.0,
                speed=40.0,
                body=(GripperStep(action=GripperAction.CLOSE, timeout_ms=200),),
            ),
        ),
    )
    looped = Program(
        name="loop",
        waypoints=POINTS,
        steps=(
            LoopStep(
                times=3,
                body=(
                    MoveStep(waypoint="P1", speed=60.0),
                    WaitStep(ms=250),
                    MoveStep(waypoint="P2", speed=60.0),
                ),
            ),
        ),
    )
    return {
        "pick_and_place.json": pick,
        "linear": linear,
        "blended": blended,
        "pallet (4 cells)": pallet,
        "loop": looped,
    }


def long_program() -> Program:
    """~60 s: ten passes of a pick at one pallet cell, a place, waits and the gripper."""
    body = (
        MoveStep(waypoint="P1", speed=40.0),
        GripperStep(action=GripperAction.OPEN, timeout_ms=300),
        PalletStep(
            corners=("P3", "P4", "P5"),
            rows=2,
            columns=2,
            approach_mm=60.0,
            speed=30.0,
            body=(GripperStep(action=GripperAction.CLOSE, timeout_ms=300),),
        ),
        MoveStep(waypoint="P2", speed=40.0),
        MoveStep(waypoint="P2", motion=MotionType.LINEAR, offset=UP, speed=20.0),
        WaitStep(ms=500),
    )
    return Program(name="sixty", waypoints=POINTS, steps=(LoopStep(times=10, body=body),))


def cell() -> list[BoxObstacle]:
    """Two boxes beside the arm, clear of its moves (every clearance is computed, none refuses)."""
    boxes = []
    for name, (x, y, z) in {
        "table": (0.0, 0.0, -0.05),
        "rack": (0.8, 0.0, 0.4),
        "fence": (0.0, -0.9, 0.5),
    }.items():
        sides = {"table": (1.5, 1.5, 0.02), "rack": (0.1, 1.0, 0.8), "fence": (1.5, 0.05, 1.0)}[name]
        boxes.append(
            BoxObstacle.model_validate(
                {
                    "obstacleType": "BOX",
                    "name": name,
                    "sides": dict(zip("xyz", sides, strict=True)),
                    "centerPosition": {
                        "point": {"x": x, "y": y, "z": z},
                        "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0},
                    },
                }
            )
        )
    return boxes[1:]  # the table would be below the floor: the floor is already checked


def real_run(program: Program, clock: ScaledClock | MonotonicClock) -> tuple[float, dict[int, float]]:
    """The program run on the embedded simulator in real time (the runner polling it as on an arm), timed on
    `clock`: a ScaledClock holds simulated time while the simulator plans (the motion alone), the
    MonotonicClock (`pendant run`'s) counts the planning too. Per-line times as the runner reports lines."""
    sim = SimController(clock=clock)
    runner = ProgramRunner(sim, now=clock.now)
    per_line: dict[int, float] = {}
    current: list[tuple[int, float]] = []

    def listen(progress: RunProgress) -> None:
        if progress.state is RunState.RUNNING and progress.step_index is not None:
            if current and current[-1][0] == progress.step_index:
                return
            now = clock.now()
            if current:
                line, since = current[-1]
                per_line[line] = per_line.get(line, 0.0) + now - since
            current.append((progress.step_index, now))

    runner.add_listener(listen)
    started = clock.now()
    result = runner.run(program)
    ended = clock.now()
    if current:
        line, since = current[-1]
        per_line[line] = per_line.get(line, 0.0) + ended - since
    assert result.state is RunState.FINISHED, result.message
    return ended - started, per_line


def main() -> None:
    seed = read_seed(SimController(clock=FakeClock()))
    sixty = long_program()
    reports: list[PreflightReport] = []
    walls = wall_times_s(lambda: reports.append(preflight(sixty, seed.with_cell(cell(), None))), REPEATS)
    report = reports[-1]
    assert report.ok, report.summary
    print(f"Pre-flight of a {report.cycle_time_s:.1f} s program ({len(report.steps)} lines, 2 obstacles, ")
    print(f"  clearance on every step): {statistics.median(walls):.2f} s wall (median of {REPEATS})")
    walls = wall_times_s(lambda: preflight(sixty, seed), REPEATS)
    print(f"The same without obstacles: {statistics.median(walls):.2f} s wall (median of {REPEATS})")
    print()
    columns = ("pre-flight", 11), ("run", 8), ("error", 8), ("worst step", 12), ("run+plan", 10), ("error", 8)
    print(f"{'program':<22}" + "".join(f"{name:>{width}}" for name, width in columns))
    for name, program in programs().items():
        checked = preflight(program, seed)
        assert checked.ok, checked.summary
        run_s, per_line = real_run(program, ScaledClock(1.0))
        worst = max(
            (abs(step.duration_s - per_line.get(step.line - 1, 0.0)) for step in checked.steps), default=0.0
        )
        wall_s, _ = real_run(program, MonotonicClock())
        error = (checked.cycle_time_s - run_s) / run_s
        wall_error = (checked.cycle_time_s - wall_s) / wall_s
        print(
            f"{name:<22}{checked.cycle_time_s:>10.3f}s{run_s:>7.3f}s{error:>+8.1%}{worst:>11.3f}s"
            f"{wall_s:>9.3f}s{wall_error:>+8.1%}"
        )
    print()
    print("run: the simulator's own run on its clock (planning holds it); run+plan: on the wall clock, as")
    print(
        "`pendant run` does, the simulator's planning time included; worst step: largest per-step difference."
    )


if __name__ == "__main__":
    main()
