"""What obstacles and a tool shape cost a motion: planning time of the same moves in an empty cell and in a
cell with boxes, a capsule, a plane and a two-capsule tool (none in the way), side by side; and the cost of
one collision check of a configuration against that cell: the former check (the arm's own pairs, then a
Python loop over coal pairs, kept as the tests' reference) and the ONE cell check (kinematics/cell_check.py),
one configuration at a time and in batches of 1,000, side by side in one run.

Run: PYTHONPATH=. python benchmarks/environment.py
"""

from __future__ import annotations

import os
import statistics
import time
from collections.abc import Callable

import numpy as np

from pendant.controller.cell_types import (
    BoxObstacle,
    CapsuleObstacle,
    PlaneObstacle,
    SimplifiedCapsuleObstacle,
    ToolShape,
)
from pendant.controller.system_types import JointMotionParameters, LinearMotionParameters, PositionWaypoint
from pendant.controller.types import Point, Position, Rotation
from pendant.sim import FakeClock, SimController
from tests.support.reference_cell_check import CellGeometry

REPEATS = 7
CHECKS = 1000
LINEAR = LinearMotionParameters(velocity=0.5, acceleration=2.0)
JOINT = JointMotionParameters(velocity=50, acceleration=50)
LEVEL = Rotation(roll=0.0, pitch=0.0, yaw=0.0)


def _at(x: float, y: float, z: float) -> Position:
    return Position(point=Point(x=x, y=y, z=z), rotation=LEVEL)


def furnish(sim: SimController) -> None:
    for k, (x, y) in enumerate([(0.6, 0.6), (0.6, -0.6), (-0.2, 0.7), (0.7, 0.0)]):
        sides = Point(x=0.2, y=0.2, z=0.2)
        sim.add_obstacle(
            BoxObstacle(obstacleType="BOX", name=f"box{k}", sides=sides, centerPosition=_at(x, y, 0.1))
        )
    sim.add_obstacle(
        CapsuleObstacle(
            obstacleType="CAPSULE",
            name="pole",
            radius=0.05,
            begin=Point(x=0.5, y=0.5, z=0),
            finish=Point(x=0.5, y=0.5, z=1),
        )
    )
    wall = [Point(x=-1.0, y=0.0, z=0.0), Point(x=-1.0, y=1.0, z=0.0), Point(x=-1.0, y=0.0, z=1.0)]
    sim.add_obstacle(PlaneObstacle(obstacleType="PLANE", name="wall", points=wall))
    capsules = [
        SimplifiedCapsuleObstacle(radius=0.03, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.08)),
        SimplifiedCapsuleObstacle(
            radius=0.015, begin=Point(x=0, y=0.02, z=0.08), finish=Point(x=0, y=0.02, z=0.12)
        ),
    ]
    sim.set_tool_shape(ToolShape(shape=capsules))


def plan_seconds(sim: SimController, move: Callable[[SimController], object]) -> float:
    times = []
    for _ in range(REPEATS):
        sim.freeze()
        started = time.perf_counter()
        move(sim)
        times.append(time.perf_counter() - started)
    sim.freeze()
    return statistics.median(times)


def main() -> None:
    empty, furnished = SimController(clock=FakeClock()), SimController(clock=FakeClock())
    furnish(furnished)
    here = empty.get_position()

    def beside(dy: float) -> PositionWaypoint:
        return PositionWaypoint(
            point=Point(x=here.point.x, y=here.point.y + dy, z=here.point.z), rotation=here.rotation
        )

    moves: dict[str, Callable[[SimController], object]] = {
        "LINEAR 30 cm": lambda sim: sim.run_linear_positions([beside(0.3)], LINEAR),
        "LINEAR 3 waypoints, blend 2 cm": lambda sim: sim.run_linear_positions(
            [beside(0.1).model_copy(update={"blend": 0.02}), beside(0.2), beside(0.3)], LINEAR
        ),
        "JOINT 30 cm": lambda sim: sim.run_joint_positions([beside(0.3)], JOINT),
    }
    print(f"{'move':34} {'empty cell':>12} {'furnished':>12} {'ratio':>7}")
    for name, move in moves.items():
        bare, busy = plan_seconds(empty, move), plan_seconds(furnished, move)
        print(f"{name:34} {bare * 1e3:9.1f} ms {busy * 1e3:9.1f} ms {busy / bare:6.1f}x")
    compare_checks(furnished)


def compare_checks(furnished: SimController) -> None:
    arm = furnished.arm
    new = furnished._environment.geometry
    old = CellGeometry(arm, [(o.shape, o.T) for o in new.obstacles], list(new.tool))
    rng = np.random.default_rng(0)
    near = furnished.joint_positions() + rng.normal(0, 0.01, (CHECKS, 6))  # clear: every pair is checked
    anywhere = rng.uniform(arm.lower, arm.upper, (CHECKS, 6))  # about 70 % in some collision

    def per_check_us(check: Callable[[np.ndarray], object], qs: np.ndarray) -> float:
        started = time.perf_counter()
        for q in qs:
            check(q)
        return (time.perf_counter() - started) / len(qs) * 1e6

    def batch_us(qs: np.ndarray) -> float:
        started = time.perf_counter()
        new.collides_many(qs)
        return (time.perf_counter() - started) / len(qs) * 1e6

    print(f"\none configuration against 6 obstacles and 2 tool capsules (load {os.getloadavg()[0]:.1f}):")
    print(f"{'configurations':26} {'former':>10} {'new, one':>10} {'new, 1000':>10} {'ratio':>7}")
    for name, qs in (("clear (near the start)", near), ("random (limits)", anywhere)):
        before = per_check_us(lambda q: arm.in_collision(q) or old.collides(q), qs)
        after = per_check_us(new.collides, qs)
        batched = batch_us(qs)
        print(f"{name:26} {before:7.0f} us {after:7.1f} us {batched:7.1f} us {before / after:6.0f}x")


if __name__ == "__main__":
    main()
