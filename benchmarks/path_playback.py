"""Path steps: how closely a recorded path plays back, on the simulator's fake clock.

A hand-drawn S (the arm pulled by hand in free drive through 91 poses at 30 Hz: J1 sweeps 40° while J2, J3
and J5 bend and come back, 0.51 m of TCP travel) is recorded, turned into a Path step at several tolerances
and played by the runner, the TCP read every 2 ms of simulated time. Prints, per tolerance: the waypoints
kept, the largest distance from a recorded sample to the played path and from a played sample to the
recorded path (mm), the largest orientation error (degrees), the playing time, and the same path played
stop-and-go (a controller without /run/*) for comparison.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
from fastapi.testclient import TestClient

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from pendant.api import create_app
from pendant.kinematics.transforms import position_to_matrix
from pendant.program import Program, ProgramRunner
from pendant.remote import RemoteController
from pendant.sim import FakeClock, SimController
from pendant.teach.path_step import path_step
from tests.support.deviation import max_deviation_mm, max_turn_deg, start_index
from tests.support.path_playback import (
    SAMPLE_S,
    Sampler,
    WithoutRunOperations,
    hand_drawn_s,
    recorded_points,
)

TOLERANCES = ((0.5, 0.5), (1.0, 1.0), (2.0, 2.0), (5.0, 5.0))


def play(tol_mm: float, tol_deg: float, older: bool) -> str:
    clock = FakeClock()
    sim = SimController(clock=clock)
    recording = hand_drawn_s(sim, clock)
    step = path_step(recording, tol_mm, tol_deg)
    sampler = Sampler(sim, clock)
    started = time.perf_counter()
    if older:
        with TestClient(WithoutRunOperations(create_app(sim))) as http:
            runner = ProgramRunner(
                RemoteController("http://testserver", client=http), sleep=sampler, now=clock.now
            )
            runner.run(Program(steps=(step,)))
    else:
        ProgramRunner(sim, sleep=sampler, now=clock.now).run(Program(steps=(step,)))
    wall = time.perf_counter() - started
    recorded = recorded_points(recording)
    start = start_index(sampler.played, recorded[0])
    there, back = max_deviation_mm(recorded, sampler.played[start:])
    recorded_poses = np.array([position_to_matrix(s.tcp) for s in recording.samples])
    turned = max_turn_deg(recorded_poses, np.array(sampler.poses[start:]))
    played_s = len(sampler.poses[start:]) * SAMPLE_S
    how = "stop-and-go" if older else "blended   "
    return (
        f"{tol_mm:4.1f} mm / {tol_deg:3.1f}°  {how}  {len(step.points):3d} waypoints  "
        f"recorded->played {there:.3f} mm  played->recorded {back:.3f} mm  turn {turned:.3f}°  "
        f"path {played_s:5.2f} s (simulated; {wall:.1f} s wall)"
    )


def main() -> None:
    for tol_mm, tol_deg in TOLERANCES:
        for older in (False, True):
            print(play(tol_mm, tol_deg, older), flush=True)


if __name__ == "__main__":
    main()
