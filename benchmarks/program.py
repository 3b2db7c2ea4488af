"""Program benchmarks: what the plan and the interpreter add on top of the controller calls.

Prints
- the time to compile a large program (a 10x10x10 pallet inside a loop, 1,000 moves, nested Ifs),
- the interpreter's cost per step: a program of 2,000 output steps (inside loops and Ifs) run on the
  simulator's fake clock, against the same 2,000 set_output calls made directly (side by side: a ratio),
- loading and saving it (JSON, validated, atomic write).
"""

from __future__ import annotations

import statistics
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks._timing import wall_times_s
from pendant.controller.types import MotionParams, Pose, SignalLevel
from pendant.program import (
    IfStep,
    LoopStep,
    MoveStep,
    OutputStep,
    PalletStep,
    Program,
    ProgramRunner,
    ProgramStore,
    Waypoint,
    compile_program,
)
from pendant.sim import FakeClock, SimController

REPEATS = 5


def waypoints(sim: SimController, clock: FakeClock) -> tuple[Waypoint, ...]:
    taught = []
    for k, j1 in enumerate((20.0, -20.0, 0.0)):
        sim.set_pose(Pose(angles=[j1, -90.0, 90.0, -90.0, -90.0, 0.0]), MotionParams(speed=100.0))
        clock.advance(max(0.0, sim.busy_until() - clock.now()))
        taught.append(Waypoint(name=f"P{k + 1}", pose=sim.get_pose(), position=sim.get_position()))
    return tuple(taught)


def best_of(action: Callable[[], object]) -> float:
    return min(wall_times_s(action, REPEATS))


def main() -> None:
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    table = waypoints(sim, clock)
    big = Program(
        waypoints=table,
        steps=(
            LoopStep(
                times=3,
                body=(
                    PalletStep(
                        corners=("P1", "P2", "P3"), rows=10, columns=10, layers=10, layer_height_mm=20.0
                    ),
                    *(MoveStep(waypoint=f"P{1 + k % 3}") for k in range(1000)),
                    IfStep(then=(OutputStep(port=1, level=SignalLevel.HIGH),)),
                ),
            ),
        ),
    )
    print(f"compile: 1,000 moves + a 1,000-cell pallet: {best_of(lambda: compile_program(big)) * 1e3:.1f} ms")

    outputs = Program(
        steps=(
            LoopStep(
                times=100,
                body=tuple(
                    IfStep(
                        port=1,
                        level=SignalLevel.LOW,
                        then=(OutputStep(port=1 + k % 2, level=SignalLevel.HIGH),),
                    )
                    for k in range(20)
                ),
            ),
        )
    )
    runner = ProgramRunner(sim, sleep=clock.advance, now=clock.now)
    per_step = [best_of(lambda: runner.run(outputs)) / 2000 * 1e6 for _ in range(3)]
    direct = [
        best_of(lambda: [sim.set_output(1 + k % 2, SignalLevel.HIGH) for k in range(2000)]) / 2000 * 1e6
    ]
    interp = statistics.median(per_step)
    print(
        f"interpreter: {interp:.1f} µs per step (an If and an output) vs {direct[0]:.1f} µs per direct "
        f"set_output: x{interp / direct[0]:.1f}"
    )

    with tempfile.TemporaryDirectory() as folder:
        store = ProgramStore(folder)
        save = best_of(lambda: store.save(big, "big")) * 1e3
        load = best_of(lambda: store.load("big")) * 1e3
    print(f"save / load of that program: {save:.1f} / {load:.1f} ms")


if __name__ == "__main__":
    main()
