"""What the cell costs the target ghost: check_joint_target (limits, self-collision, the cell at the target
and along the joint path) with 0, 10 and 50 obstacles and a tool capsule, for a 90° joint-1 move; beside it,
the same path checked sample by sample with the former cell check (tests/kinematics/reference_cell_check.py,
a Python loop over coal pairs); and the
memory the checks leave held (a drag of the gizmo checks a path on every move).

Run: PYTHONPATH=. python benchmarks/cell_check.py
"""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller import Point, Position, Rotation
from pendant.controller.cell_types import BoxObstacle, SimplifiedCapsuleObstacle, ToolShape
from pendant.kinematics.cell_shapes import obstacle_shape
from pendant.kinematics.obstacles import Capsule
from pendant.sim import SimController
from pendant.ui.target.check import check_joint_target
from tests.support.reference_cell_check import CellGeometry

RUNS = 200


def far_boxes(n: int) -> list[BoxObstacle]:
    """Boxes around the cell's edge, clear of the arm: the check must look at every one of them."""
    angles = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return [
        BoxObstacle(
            obstacleType="BOX",
            name=f"b{i}",
            sides=Point(x=0.1, y=0.1, z=0.1),
            centerPosition=Position(
                point=Point(x=1.2 * np.cos(a), y=1.2 * np.sin(a), z=0.3),
                rotation=Rotation(roll=0, pitch=0, yaw=0),
            ),
        )
        for i, a in enumerate(angles)
    ]


def main() -> None:
    sim = SimController("pulse75")
    q = np.radians(sim.get_pose().angles)
    target = q.copy()
    target[0] += np.radians(90.0)
    capsule = SimplifiedCapsuleObstacle(
        radius=0.03, begin=Point(x=0, y=0, z=0), finish=Point(x=0, y=0, z=0.15)
    )
    tool = ToolShape(shape=[capsule])
    for n in (0, 10, 50):
        boxes = far_boxes(n)
        cell = CellModel(sim.arm, boxes, tool) if n else None
        times = []
        for _ in range(RUNS):
            started = time.perf_counter()
            check = check_joint_target(sim.arm, target, cell, q)
            times.append(time.perf_counter() - started)
        assert check.ok
        median, p99 = np.median(times) * 1000, np.percentile(times, 99) * 1000
        line = f"{n:3d} obstacles: median {median:.2f} ms, p99 {p99:.2f} ms"
        if n:
            plain = CellGeometry(
                sim.arm,
                [obstacle_shape(b) for b in boxes],
                [Capsule(0.03, np.zeros(3), np.array([0, 0, 0.15]))],
            )
            samples = [q + f * (target - q) for f in np.linspace(0.0, 1.0, 46)]  # the same 2° steps
            started = time.perf_counter()
            for _ in range(RUNS // 20):
                assert not any(plain.collides(x) for x in samples)
            seconds = (time.perf_counter() - started) / (RUNS // 20)
            ms = seconds * 1000
            line += f"; sample by sample with the former check {ms:.1f} ms ({ms / median:.1f}x)"
        if n:
            tracemalloc.start()
            for _ in range(RUNS):
                check_joint_target(sim.arm, target, cell, q)
            held, _ = tracemalloc.get_traced_memory()
            tracemalloc.stop()
            line += f"; memory held after {RUNS} checks {held / 1e6:.1f} MB"
        print(line)


if __name__ == "__main__":
    main()
