"""What the contact rule costs: planning the same move (PUT /pose, the base turned 15 degrees) with the SDK
README's wall touching the arm at the start (the rule measures the depth at every sample in contact) and
with the same wall 10 cm further out (clear: the yes/no check alone), side by side; and one yes/no check
against one depth query of a configuration in contact.

Run: PYTHONPATH=. python benchmarks/contact.py
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks._timing import wall_times_s
from pendant.controller.cell_types import PlaneObstacle
from pendant.controller.types import MotionParams, Point, Pose
from pendant.sim import FakeClock, SimController

REPEATS = 9
CALLS = 200
OUT = Pose(angles=[15.0, -90.0, 90.0, -90.0, -90.0, 0.0])
SPEED = MotionParams(speed=50.0)


def wall(x: float) -> PlaneObstacle:
    points = [Point(x=x, y=0.4, z=0.0), Point(x=x, y=0.0, z=0.0), Point(x=x, y=0.0, z=0.1)]
    return PlaneObstacle(obstacleType="PLANE", name="wall", points=points)


def median_s(action: Callable[[], object], repeats: int = REPEATS) -> float:
    return statistics.median(wall_times_s(action, repeats))


def per_call_us(call: Callable[[], object]) -> float:
    return median_s(lambda: [call() for _ in range(CALLS)]) / CALLS * 1e6


def plan_seconds(sim: SimController) -> float:
    """Median time to accept the move; the fake clock never runs, so each freeze leaves the arm at home."""
    times = []
    for _ in range(REPEATS):
        sim.freeze()
        started = time.perf_counter()
        sim.set_pose(OUT, SPEED)
        times.append(time.perf_counter() - started)
    sim.freeze()
    return statistics.median(times)


def main() -> None:
    touching, clear = SimController(clock=FakeClock()), SimController(clock=FakeClock())
    touching.add_obstacle(wall(-0.5))
    clear.add_obstacle(wall(-0.6))
    q = np.radians(touching.get_pose().angles)
    geometry = touching._environment.geometry
    depth_mm = geometry.contacts(q)["wall"].depth_m * 1000.0
    rows = [
        ("plan PUT /pose, wall clear of the arm", plan_seconds(clear) * 1e3, "ms"),
        (f"plan PUT /pose, wall {depth_mm:.0f} mm into the arm", plan_seconds(touching) * 1e3, "ms"),
        ("one yes/no check in contact", per_call_us(lambda: geometry.collides(q)), "us"),
        ("one depth query in contact", per_call_us(lambda: geometry.contacts(q)), "us"),
    ]
    width = max(len(name) for name, _, _ in rows)
    print(f"{'measure':<{width}}  median")
    for name, value, unit in rows:
        print(f"{name:<{width}}  {value:7.2f} {unit}")


if __name__ == "__main__":
    main()
