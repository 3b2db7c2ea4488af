"""The simulator as a test double (the pulse_sim fixture): how fast, how exact, how many at once.

Prints
- a 60 s program (moves and gripper waits) run over HTTP against the fixture's simulator at time scales
  10 to 1000, two ways: paced by the client (each command sent when the last one ended, status polled every
  millisecond, as robot code does) and queued (every command sent at once): wall time, simulated seconds per
  wall second, and how far the simulated duration is from the planned one (exact: within 1 %);
- the first fixture's start (imports, model, server, first answer) in a fresh process, and the per-test reset;
- N simulators running that program in parallel processes (xdist workers) on this machine.
Targets: a 60 s program in <= 1.5 s of wall time while exact; reset <= 20 ms; first fixture ready <= 1.5 s.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

import httpx

REPO_ROOT = Path(__file__).resolve().parents[1]
if str(REPO_ROOT) not in sys.path:
    sys.path.insert(0, str(REPO_ROOT))

from pendant.controller.types import MotionParams, Pose  # noqa: E402
from pendant.sim import ScaledClock, SimController  # noqa: E402
from pendant.simserver import SimServer  # noqa: E402

PICK = [60.0, -60.0, 100.0, -130.0, -90.0, 0.0]
PLACE = [-60.0, -70.0, 110.0, -130.0, -90.0, 30.0]
SPEED = 10.5
GRIPPER_MS = 800
CYCLES = 3  # of pick, close, place, open: about 60 simulated seconds
SCALES = (10.0, 30.0, 100.0, 300.0, 1000.0)
EXACT = 0.01
POLL_S = 0.001
PARALLEL = (1, 2, 4)
PARALLEL_SCALE = 30.0


def program() -> list[tuple[str, dict[str, object], dict[str, object] | None]]:
    """(path, query, body) of each command."""
    steps: list[tuple[str, dict[str, object], dict[str, object] | None]] = []
    for _ in range(CYCLES):
        steps.append(("/pose", {"speed": SPEED}, {"angles": PICK}))
        steps.append(("/gripper/close", {"timeout": GRIPPER_MS}, None))
        steps.append(("/pose", {"speed": SPEED}, {"angles": PLACE}))
        steps.append(("/gripper/open", {"timeout": GRIPPER_MS}, None))
    return steps


def planned_duration() -> float:
    """The program's length in simulated seconds: queued on a simulator whose clock does not move."""
    clock = ScaledClock(1.0, wall=lambda: 0.0)
    sim = SimController(clock=clock)
    for _ in range(CYCLES):
        sim.set_pose(Pose(angles=PICK), MotionParams(speed=SPEED))
        sim.close_gripper(GRIPPER_MS)
        sim.set_pose(Pose(angles=PLACE), MotionParams(speed=SPEED))
        sim.open_gripper(GRIPPER_MS)
    return sim.busy_until()


def wait_idle(client: httpx.Client) -> None:
    while client.get("/status/motion").json() == "RUNNING":
        time.sleep(POLL_S)


def run_program(client: httpx.Client, server: SimServer, paced: bool) -> tuple[float, float]:
    """(wall seconds, simulated seconds) of one run of the program, from its first command (when the
    simulator started it) to the arm at rest: paced, when the client saw it (its reaction time counts);
    queued, when the simulator ended it (a queue that ran dry between two commands counts)."""
    start_wall, start_sim = time.perf_counter(), None
    for path, query, body in program():
        client.put(path, params=query, json=body).raise_for_status()
        if start_sim is None:
            start_sim = server.sim.queued_motions()[0].t0
        if paced:
            wait_idle(client)
    ends_at = server.sim.busy_until()
    wait_idle(client)
    wall = time.perf_counter() - start_wall
    end_sim = client.get("/sim/clock").json()["time"] if paced else ends_at
    end = client.get("/pose").json()["angles"]
    assert max(abs(a - b) for a, b in zip(end, PLACE, strict=True)) < 1e-6, "the program ended elsewhere"
    assert start_sim is not None
    return wall, end_sim - start_sim


def time_scales(planned: float) -> None:
    print(f"60 s program: {len(program())} commands, planned {planned:.2f} simulated s")
    print("  scale | paced: wall s, sim s / wall s, error | queued: wall s, sim s / wall s, error")
    best = None
    with SimServer() as server, httpx.Client(base_url=server.url, timeout=30.0) as client:
        for scale in SCALES:
            cells = []
            for paced in (True, False):
                server.reset(scale)  # from the power-on pose, as planned
                wall, simulated = run_program(client, server, paced)
                error = simulated / planned - 1.0
                cells.append(f"{wall:6.2f}, {simulated / wall:6.1f}, {100 * error:+6.2f} %")
                if paced and abs(error) <= EXACT:
                    best = (scale, wall, simulated / wall)
            print(f"  {scale:5g} | {cells[0]}         | {cells[1]}")
    if best is not None:
        print(
            f"  highest exact scale, client-paced: {best[0]:g} -> the 60 s program in {best[1]:.2f} s "
            f"wall ({best[2]:.0f} simulated s per wall s)"
        )


START_SCRIPT = """
import time
t0, c0 = time.perf_counter(), time.process_time()
import httpx
from pendant.simserver import SimServer
imported = time.perf_counter()
server = SimServer().start()
httpx.get(server.url + "/robot/id").raise_for_status()
print(time.perf_counter() - t0, time.process_time() - c0, imported - t0)
server.stop()
"""


def first_fixture() -> None:
    walls, cpus, imports = [], [], []
    for _ in range(3):
        out = subprocess.run(
            [sys.executable, "-c", START_SCRIPT], cwd=REPO_ROOT, capture_output=True, text=True, check=True
        ).stdout
        wall, cpu, imported = (float(word) for word in out.split())
        walls.append(wall)
        cpus.append(cpu)
        imports.append(imported)
    print(
        f"first fixture ready (fresh process: imports, model, server, first answer): {_spread(walls)} s wall "
        f"({_spread(cpus)} s CPU; the imports {_spread(imports)} s of it)"
    )


def resets() -> None:
    with SimServer() as server, httpx.Client(base_url=server.url) as client:
        times = []
        for _ in range(300):
            client.put("/pose", params={"speed": SPEED}, json={"angles": PICK}).raise_for_status()
            client.put("/signal/output/1/high").raise_for_status()
            t0 = time.perf_counter()
            server.reset(10.0)
            times.append(time.perf_counter() - t0)
        assert client.get("/status/motion").json() == "IDLE"
    times.sort()
    print(
        f"per-test reset (arm moving, outputs set): median {1e3 * statistics.median(times):.3f} ms, "
        f"p99 {1e3 * times[int(0.99 * len(times))]:.3f} ms"
    )


WORKER_SCRIPT = f"""
import json, sys, httpx
sys.path.insert(0, {str(REPO_ROOT)!r})
from benchmarks.sim_plugin import run_program
from pendant.simserver import SimServer
with SimServer(time_scale={PARALLEL_SCALE}) as server, httpx.Client(base_url=server.url, timeout=30) as c:
    print(json.dumps(run_program(c, server, paced=True)))
"""


def parallel(planned: float) -> None:
    print(f"N simulators in parallel processes, each the client-paced program at scale {PARALLEL_SCALE:g}:")
    for n in PARALLEL:
        workers = [
            subprocess.Popen([sys.executable, "-c", WORKER_SCRIPT], cwd=REPO_ROOT, stdout=subprocess.PIPE)
            for _ in range(n)
        ]
        results = [json.loads(worker.communicate()[0]) for worker in workers]
        walls = [wall for wall, _ in results]
        errors = [100 * (simulated / planned - 1.0) for _, simulated in results]
        total = sum(simulated for _, simulated in results) / max(walls)
        print(
            f"  N={n}: wall {_spread(walls)} s each, error {min(errors):+.2f} .. {max(errors):+.2f} %, "
            f"{total:.0f} simulated s per wall s in all"
        )


def _spread(values: list[float]) -> str:
    return f"{min(values):.2f}" if len(values) == 1 else f"{min(values):.2f}-{max(values):.2f}"


def main() -> None:
    planned = planned_duration()
    time_scales(planned)
    resets()
    first_fixture()
    parallel(planned)


if __name__ == "__main__":
    main()
