"""Motion benchmarks of the simulator: timing against the real clock, LINEAR straightness, call costs.

Prints
- executed vs planned durations with the real monotonic clock (target: within 1 %),
- the largest deviation of LINEAR paths from their lines, sampled every 0.5 ms (target: < 0.1 mm),
- blended /poses/run vs the same waypoints as separate PUT /pose commands,
- the cost of get_pose / get_position / get_motors and of planning a command.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from pendant.controller.types import (
    MotionParams,
    MotionStatus,
    MotionType,
    Point,
    Pose,
    Position,
    Rotation,
    Tool,
)
from pendant.kinematics.transforms import position_to_matrix
from pendant.sim import FakeClock, MonotonicClock, SimController

JOINT_MOVES = [
    ("JOINT 100% long", Pose(angles=[170.0, -100.0, 100.0, -30.0, -150.0, 120.0]), MotionParams(speed=100)),
    ("JOINT 50%", Pose(angles=[40.0, -70.0, 60.0, -100.0, -60.0, 30.0]), MotionParams(speed=50)),
    ("JOINT 20% short", Pose(angles=[5.0, -88.0, 92.0, -90.0, -90.0, 3.0]), MotionParams(speed=20)),
]


def _xyz(p: Position) -> np.ndarray:
    return np.array([p.point.x, p.point.y, p.point.z])


def _shifted(
    p: Position, dx: float, dy: float, dz: float, droll: float = 0.0, dpitch: float = 0.0
) -> Position:
    return Position(
        point=Point(x=p.point.x + dx, y=p.point.y + dy, z=p.point.z + dz),
        rotation=Rotation(roll=p.rotation.roll + droll, pitch=p.rotation.pitch + dpitch, yaw=p.rotation.yaw),
    )


def timing_against_the_real_clock() -> None:
    print("executed vs planned duration (MonotonicClock, status polled every ~0.5 ms)")
    sim = SimController("pulse75", MonotonicClock())
    commands = [
        (name, lambda pose=pose, params=params: sim.set_pose(pose, params))
        for name, pose, params in JOINT_MOVES
    ]
    commands.append(
        (
            "LINEAR 50% 30 cm",
            lambda: sim.set_position(
                _shifted(sim.get_position(), -0.2, 0.2, -0.1),
                MotionParams(speed=50, motion_type=MotionType.LINEAR),
            ),
        )
    )
    commands.append(
        (
            "poses/run 3 waypoints",
            lambda: sim.run_poses(
                [
                    Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, 10.0]),
                    Pose(angles=[40.0, -60.0, 60.0, -100.0, -90.0, 30.0]),
                    Pose(angles=[0.0, -90.0, 90.0, -90.0, -90.0, 0.0]),
                ],
                MotionParams(speed=60),
            ),
        )
    )
    worst = 0.0
    for name, command in commands:
        start = time.monotonic()
        command()
        planned = sim.busy_until() - start
        while sim.get_motion_status() is MotionStatus.RUNNING:
            time.sleep(0.0005)
        executed = time.monotonic() - start
        error = 100.0 * (executed - planned) / planned
        worst = max(worst, abs(error))
        print(f"  {name:24s} planned {planned:7.4f} s  executed {executed:7.4f} s  error {error:+.3f} %")
    print(f"  worst |error| {worst:.3f} % (target <= 1 %)")


def linear_straightness() -> None:
    print("LINEAR paths: largest distance from the line, sampled every 0.5 ms (FakeClock)")
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    gripper = Tool(
        name="gripper",
        point=Point(x=0.0, y=0.0, z=0.15),
        rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
        radius=0.04,
    )
    cases = [
        ("30 cm, fixed orientation", None, (-0.2, 0.2, -0.1, 0.0, 0.0), 100.0),
        ("25 cm, turning 0.5 rad", None, (0.1, 0.2, 0.1, 0.3, 0.4), 100.0),
        ("20 cm with a 15 cm tool", gripper, (-0.15, -0.1, 0.1, 0.0, 0.3), 50.0),
        ("40 cm slow", None, (0.0, 0.4, 0.0, 0.0, 0.0), 10.0),
    ]
    worst = 0.0
    for name, tool, (dx, dy, dz, droll, dpitch), speed in cases:
        sim.reset()
        if tool is not None:
            sim.set_tool(tool)
        start = sim.get_position()
        target = _shifted(start, dx, dy, dz, droll, dpitch)
        t0 = time.perf_counter()
        sim.set_position(target, MotionParams(speed=speed, motion_type=MotionType.LINEAR))
        plan_ms = 1000 * (time.perf_counter() - t0)
        p0, p1 = _xyz(start), _xyz(target)
        direction = (p1 - p0) / np.linalg.norm(p1 - p0)
        deviation = 0.0
        n = 0
        while sim.get_motion_status() is MotionStatus.RUNNING:
            offset = _xyz(sim.get_position()) - p0
            deviation = max(deviation, float(np.linalg.norm(offset - (offset @ direction) * direction)))
            clock.advance(0.0005)
            n += 1
        end_error = float(np.max(np.abs(position_to_matrix(sim.get_position()) - position_to_matrix(target))))
        worst = max(worst, deviation)
        print(
            f"  {name:28s} max deviation {1000 * deviation:.5f} mm over {n} samples;"
            f" end error {end_error:.1e}; planned in {plan_ms:.1f} ms"
        )
    print(f"  worst deviation {1000 * worst:.5f} mm (target < 0.1 mm)")


def blended_vs_stop_and_go() -> None:
    print("PUT /poses/run vs the same waypoints as separate PUT /pose commands (60 %)")
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    waypoints = [
        Pose(angles=[20.0, -80.0, 80.0, -90.0, -70.0, 10.0]),
        Pose(angles=[40.0, -60.0, 60.0, -100.0, -90.0, 30.0]),
        Pose(angles=[60.0, -80.0, 70.0, -80.0, -90.0, 0.0]),
        Pose(angles=[0.0, -90.0, 90.0, -90.0, -90.0, 0.0]),
    ]
    params = MotionParams(speed=60)
    sim.run_poses(waypoints, params)
    blended = sim.busy_until() - clock.now()
    sim.freeze()
    sim.reset()
    for pose in waypoints:
        sim.set_pose(pose, params)
    separate = sim.busy_until() - clock.now()
    gain = 100 * (1 - blended / separate)
    print(f"  blended {blended:.3f} s, stop-and-go {separate:.3f} s ({gain:.0f} % faster)")


def _per_call_us(call: Callable[[], object], n: int = 20000) -> tuple[float, float]:
    samples = []
    for _ in range(n):
        t0 = time.perf_counter_ns()
        call()
        samples.append(time.perf_counter_ns() - t0)
    samples.sort()
    return samples[len(samples) // 2] / 1000, samples[int(len(samples) * 0.99)] / 1000


def call_costs() -> None:
    print("call costs (median / p99, microseconds)")
    clock = FakeClock()
    sim = SimController("pulse75", clock)
    print("  get_pose idle      {:7.1f} / {:7.1f}".format(*_per_call_us(sim.get_pose)))
    sim.set_pose(Pose(angles=[170.0, -100.0, 100.0, -30.0, -150.0, 120.0]), MotionParams(speed=1))
    clock.advance(1.0)
    print("  get_pose moving    {:7.1f} / {:7.1f}".format(*_per_call_us(sim.get_pose)))
    print("  get_position       {:7.1f} / {:7.1f}".format(*_per_call_us(sim.get_position)))
    print("  get_motion_status  {:7.1f} / {:7.1f}".format(*_per_call_us(sim.get_motion_status)))
    print("  get_motors         {:7.1f} / {:7.1f}".format(*_per_call_us(sim.get_motors, 2000)))
    sim.reset()
    plan_ms = []
    for name, pose, params in JOINT_MOVES:
        t0 = time.perf_counter()
        sim.set_pose(pose, params)
        plan_ms.append((name, 1000 * (time.perf_counter() - t0)))
        sim.freeze()
        sim.reset()
    print("  planning (ms): " + ", ".join(f"{name} {ms:.1f}" for name, ms in plan_ms))


def main() -> None:
    timing_against_the_real_clock()
    linear_straightness()
    blended_vs_stop_and_go()
    call_costs()


if __name__ == "__main__":
    main()
