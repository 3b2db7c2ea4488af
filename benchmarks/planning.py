"""The planner on the scenes it ships (pendant/planning/scenes.py), side by side in one run with OMPL's
defaults (no tuning, no re-check) and mplib 0.2.1: time per plan (median, p95), success, paths valid under
a dense re-check (every 0.5 degree per joint, the pendant's cell check without the margin), path length.

mplib needs numpy < 2: it runs in a venv of its own, set up on first use under .cache/venv-mplib (pip, from
PyPI), never in the project's venv; benchmarks/mplib_worker.py is its side.

Run: PYTHONPATH=. python benchmarks/planning.py [--targets 10] [--repeats 2] [--no-mplib]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from pendant.controller.errors import PreconditionFailed
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import CellCheck, bounded
from pendant.kinematics.obstacles import capsule_shape
from pendant.planning import MARGIN_M, PlannerSettings, path_is_clear, plan_joint_path
from pendant.planning.scenes import SCENES, Scene

ROOT = Path(__file__).resolve().parent.parent
MPLIB_VENV = ROOT / ".cache" / "venv-mplib"
MPLIB_REQUIREMENTS = ["mplib==0.2.1", "numpy<2"]
BUDGET_S = 1.0


@dataclass
class Outcome:
    seconds: float
    success: bool
    valid: bool
    length_deg: float


def _mplib_python() -> Path:
    python = MPLIB_VENV / "bin" / "python"
    if not python.exists():
        print(f"setting up mplib's venv in {MPLIB_VENV} ...", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", str(MPLIB_VENV)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "-q", *MPLIB_REQUIREMENTS], check=True)
    return python


def _judge(check: CellCheck, path: np.ndarray, target: np.ndarray, seconds: float) -> Outcome:
    if len(path) == 0:
        return Outcome(seconds, False, False, 0.0)
    ends_there = bool(np.allclose(path[-1], target, atol=1e-3))
    valid = ends_there and path_is_clear(check, path)
    length = float(np.degrees(np.sum(np.linalg.norm(np.diff(path, axis=0), axis=1))))
    return Outcome(seconds, True, valid, length)


def run_ours(
    check: CellCheck, start: np.ndarray, targets: list[np.ndarray], settings: PlannerSettings
) -> list[Outcome]:
    outcomes = []
    for target in targets:
        began = time.perf_counter()
        try:
            path = plan_joint_path(check, start, target, BUDGET_S, settings).waypoints
        except PreconditionFailed:
            path = np.empty((0, 6))
        outcomes.append(_judge(check, path, target, time.perf_counter() - began))
    return outcomes


def _mplib_job(
    arm: ArmModel, check: CellCheck, start: np.ndarray, targets: list[np.ndarray]
) -> dict[str, object]:
    """The cell as plain shapes for mplib: obstacles (a half-space as the same slab the pendant checks),
    the floor, the tool's capsules attached to the TCP link."""
    shapes = []
    for obstacle in check.obstacles:
        shape, T = bounded(obstacle.shape, obstacle.T)
        shapes.append({"name": obstacle.name, **_plain(shape, T)})
    shapes.append({"name": "floor", **_plain(*bounded(_floor_halfspace(), np.eye(4)))})
    model = arm.pin_arm.model
    data = model.createData()
    pin.framesForwardKinematics(model, data, np.zeros(model.nq))
    T_tcp_flange = np.linalg.inv(data.oMf[arm.pin_arm.tcp_frame_id].homogeneous) @ arm.fk(np.zeros(6))
    tool = []
    for capsule in check.tool:
        shape, T_flange_shape = capsule_shape(capsule)
        tool.append(_plain(shape, T_tcp_flange @ T_flange_shape))
    return {
        "urdf": str(arm.urdf_path),
        "move_group": "tcp",
        "obstacles": shapes,
        "tool": tool,
        "tool_link": -1,
        "base_link": "base_link",
        "start": start.tolist(),
        "targets": [t.tolist() for t in targets],
        "budget_s": BUDGET_S,
    }


def _floor_halfspace() -> object:
    import coal

    return coal.Halfspace(np.array([0.0, 0.0, 1.0]), 0.0)


def _plain(shape: object, T: np.ndarray) -> dict[str, object]:
    import coal

    if isinstance(shape, coal.Box):
        return {"kind": "box", "sides": (2.0 * np.array(shape.halfSide)).tolist(), "T": T.tolist()}
    if isinstance(shape, coal.Capsule):
        return {"kind": "capsule", "radius": shape.radius, "length": 2.0 * shape.halfLength, "T": T.tolist()}
    if isinstance(shape, coal.Sphere):
        return {"kind": "sphere", "radius": shape.radius, "T": T.tolist()}
    raise TypeError(f"no plain form for {type(shape).__name__}")


def run_mplib(arm: ArmModel, check: CellCheck, start: np.ndarray, targets: list[np.ndarray]) -> list[Outcome]:
    job = json.dumps(_mplib_job(arm, check, start, targets))
    worker = Path(__file__).with_name("mplib_worker.py")
    done = subprocess.run(
        [str(_mplib_python()), str(worker)], input=job, capture_output=True, text=True, check=True
    )
    answers = json.loads(done.stdout.strip().splitlines()[-1])
    return [
        _judge(check, np.array(a["path"]).reshape(-1, 6), target, a["seconds"])
        for a, target in zip(answers, targets, strict=True)
    ]


def _row(scene: str, planner: str, outcomes: list[Outcome]) -> str:
    times = sorted(o.seconds * 1e3 for o in outcomes)
    p95 = times[min(len(times) - 1, int(np.ceil(0.95 * len(times))) - 1)]
    found = [o for o in outcomes if o.success]
    valid = sum(o.valid for o in found)
    length = statistics.median(o.length_deg for o in found) if found else float("nan")
    return (
        f"| {scene} | {planner} | {statistics.median(times):.0f} | {p95:.0f} | "
        f"{100 * len(found) / len(outcomes):.0f} % | {valid}/{len(found)} | {length:.0f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--targets", type=int, default=10, help="targets per scene (the named one first)")
    parser.add_argument("--repeats", type=int, default=2, help="plans per target and planner")
    parser.add_argument("--no-mplib", action="store_true")
    args = parser.parse_args()
    arm = ArmModel.load("pulse75")
    planners: dict[str, Callable[[Scene, CellCheck, np.ndarray, list[np.ndarray]], list[Outcome]]] = {
        "pendant (OMPL RRT-Connect, tuned)": lambda _s, c, q, ts: run_ours(c, q, ts, PlannerSettings()),
        "OMPL defaults": lambda _s, c, q, ts: run_ours(c, q, ts, PlannerSettings(tuned=False)),
    }
    if not args.no_mplib:
        planners["mplib 0.2.1"] = lambda _s, c, q, ts: run_mplib(arm, c, q, ts)
    print(f"load average at start: {' '.join(f'{x:.1f}' for x in os.getloadavg())} on {os.cpu_count()} cores")
    print(
        f"budget {BUDGET_S:g} s a plan; margin {MARGIN_M * 1e3:g} mm (pendant); valid: clear every 0.5 degree"
    )
    print("| scene | planner | median ms | p95 ms | success | valid paths | median length (deg) |")
    print("|---|---|---|---|---|---|---|")
    for scene in SCENES:
        check = scene.check(arm)
        start = np.radians(scene.start_deg)
        targets = scene.targets(arm, args.targets, MARGIN_M) * args.repeats
        for name, run in planners.items():
            print(_row(scene.name, name, run(scene, check, start, targets)), flush=True)
    print(f"load average at end: {' '.join(f'{x:.1f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
