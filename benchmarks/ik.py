"""IK benchmark in the TRAC-IK protocol, for both PULSE models.

Run from the checkout root:

    .venv/bin/python benchmarks/ik.py            # 10,000 samples per model
    .venv/bin/python benchmarks/ik.py --samples 2000 --model pulse75

For each model: draw random joint configurations uniformly within the joint limits (fixed seed), take the
TCP pose by FK, solve `ArmModel.ik(T, q_near = midpoint of the limits)`, and count a success when the
answer reproduces the pose within 1e-5 m and 1e-5 rad. Prints the success rate, the median and p99 time
per IK call, the time per FK call, ik_all, and in_collision (when the URDF is present). A second set of
configurations at or next to the wrist and elbow singularities checks that those are solved as well.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from pendant.kinematics import ArmModel

SEED = 20240601
SUCCESS_POS_M = 1e-5
SUCCESS_ROT_RAD = 1e-5


def rotation_error(R_a: np.ndarray, R_b: np.ndarray) -> float:
    """Angle of R_a^T R_b in radians (via the skew part, accurate for small angles)."""
    R = R_a.T @ R_b
    skew = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return float(np.arctan2(0.5 * np.linalg.norm(skew), 0.5 * (np.trace(R) - 1.0)))


def reaches(arm: ArmModel, q: np.ndarray | None, T: np.ndarray) -> bool:
    if q is None:
        return False
    T_reached = arm.fk(q)
    return bool(
        np.linalg.norm(T_reached[:3, 3] - T[:3, 3]) < SUCCESS_POS_M
        and rotation_error(T_reached[:3, :3], T[:3, :3]) < SUCCESS_ROT_RAD
    )


def near_singular_configurations(arm: ArmModel, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random configurations with the wrist (q5) or the elbow (q3) put at or next to 0 or pi."""
    configurations = rng.uniform(arm.lower, arm.upper, size=(count, 6))
    joint = rng.choice([2, 4], size=count)
    base = rng.choice([0.0, np.pi, -np.pi], size=count)
    offset = rng.choice([0.0, 1e-12, -1e-9, 1e-7, -1e-6], size=count)
    configurations[np.arange(count), joint] = base + offset
    return configurations


def time_per_call_us(function: Callable[[Any], object], arguments: Sequence[Any]) -> np.ndarray:
    times = np.empty(len(arguments))
    clock = time.perf_counter
    for index, argument in enumerate(arguments):
        start = clock()
        function(argument)
        times[index] = clock() - start
    return times * 1e6


def bench_model(model: str, samples: int) -> None:
    arm = ArmModel.load(model)
    rng = np.random.default_rng(SEED)
    configurations = rng.uniform(arm.lower, arm.upper, size=(samples, 6))
    q_near = 0.5 * (arm.lower + arm.upper)

    # Warm up caches and lazy imports so the first call does not skew the percentiles.
    for q in configurations[:50]:
        arm.ik(arm.fk(q), q_near)

    fk_us = time_per_call_us(arm.fk, list(configurations))
    near_singular = near_singular_configurations(arm, rng, samples)
    targets = [arm.fk(q) for q in configurations]
    answers: list[np.ndarray | None] = []

    def solve(T: np.ndarray) -> None:
        answers.append(arm.ik(T, q_near))

    ik_us = time_per_call_us(solve, targets)
    ik_all_us = time_per_call_us(arm.ik_all, targets[: min(samples, 2000)])

    successes = sum(reaches(arm, q, T) for T, q in zip(targets, answers, strict=True))

    singular_successes = sum(reaches(arm, arm.ik(arm.fk(q), q_near), arm.fk(q)) for q in near_singular)

    print(f"{model}: {samples} random configurations, q_near = midpoint of the limits, seed {SEED}")
    print(f"  IK success       {100.0 * successes / samples:.2f} %  ({successes}/{samples})")
    print(
        f"  IK success, near-singular set  {100.0 * singular_successes / samples:.2f} %  "
        f"({singular_successes}/{samples}: q5 or q3 in {{0, pi}} +- 1e-12..1e-6)"
    )
    print(f"  IK time          median {np.median(ik_us):6.1f} us   p99 {np.percentile(ik_us, 99):6.1f} us")
    print(
        f"  ik_all time      median {np.median(ik_all_us):6.1f} us   "
        f"p99 {np.percentile(ik_all_us, 99):6.1f} us"
    )
    print(f"  FK time          median {np.median(fk_us):6.1f} us   p99 {np.percentile(fk_us, 99):6.1f} us")
    if arm.urdf_path is not None and Path(arm.urdf_path).is_file():
        collision_configs = list(configurations[: min(samples, 2000)])
        arm.in_collision(collision_configs[0])  # builds the pinocchio model
        collision_us = time_per_call_us(arm.in_collision, collision_configs)
        colliding = sum(arm.in_collision(q) for q in collision_configs)
        print(
            f"  in_collision     median {np.median(collision_us):6.1f} us   "
            f"p99 {np.percentile(collision_us, 99):6.1f} us   ({colliding}/{len(collision_configs)} random "
            "configurations in collision)"
        )


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--samples", type=int, default=10_000)
    parser.add_argument("--model", choices=["pulse75", "pulse90", "all"], default="all")
    arguments = parser.parse_args()
    models = ["pulse75", "pulse90"] if arguments.model == "all" else [arguments.model]
    for model in models:
        bench_model(model, arguments.samples)


if __name__ == "__main__":
    main()
