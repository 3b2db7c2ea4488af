"""How soon `pendant --no-ui` answers (the simulator a user's script or CI starts), and how long its first
recording takes to start: the wall clock from the start to GET /status/motion answering, the process's CPU
by then, and POST /pendant/recordings' time. With `--against DIR` (an older checkout, e.g. a
`git worktree add /tmp/old HEAD~1`), that checkout's pendant is started alternately with this one, so both
are measured side by side at the same load. With `--forked`, this checkout's pendant forked from the test
suite's preloaded interpreter (tests/support/preloaded) too, as the suite starts its pendants: the CPU a
start costs it then (the interpreter's own preloading, once per pytest process, is printed apart).

Run: .venv/bin/python benchmarks/start_up.py [--rounds 5] [--against DIR] [--forked]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.viewers import cpu_seconds
from tests.support.launchers import LOOPBACK, REPO_ROOT, free_port, stop
from tests.support.preloaded import client as preloaded
from tests.support.waiting import wait_until

ANSWER_TIMEOUT_S = 60.0
POLL_S = 0.02


def one_start(checkout: Path, data: Path, forked: bool = False) -> tuple[float, float, float]:
    """(seconds to answer, CPU-s by then, seconds for the first recording to start) of one pendant,
    exec'd or `forked` from the preloaded interpreter."""
    port = free_port()
    command = [sys.executable, "-m", "pendant", "--no-ui", "--host", LOOPBACK, "--api-port", str(port)]
    env = {**os.environ, "PYTHONPATH": str(checkout), "PENDANT_DATA_DIR": str(data)}
    began = time.monotonic()
    start = preloaded.ForkedProcess if forked else subprocess.Popen
    process = start(command, cwd=checkout, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        with httpx.Client(base_url=f"http://{LOOPBACK}:{port}", timeout=10.0) as client:
            wait_until(
                lambda: client.get("/status/motion").status_code == 200,
                ANSWER_TIMEOUT_S,
                f"{checkout}'s pendant answering",
                poll_s=POLL_S,
            )
            answered_s, answered_cpu = time.monotonic() - began, cpu_seconds(process.pid)
            asked = time.monotonic()
            started = client.post("/pendant/recordings", json={"name": "bench"})
            recording_s = time.monotonic() - asked
            if started.status_code != 201:
                raise SystemExit(
                    f"{checkout}: the recording did not start: {started.status_code} {started.text}"
                )
            client.post("/pendant/recordings/bench/stop")
    finally:
        stop(process)
    return answered_s, answered_cpu, recording_s


def summary(values: list[float]) -> str:
    return f"{statistics.median(values):.2f} ({min(values):.2f}-{max(values):.2f})"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--against", type=Path, help="an older checkout, started alternately with this one")
    parser.add_argument(
        "--forked", action="store_true", help="this checkout's pendant forked too, as the suite's"
    )
    args = parser.parse_args()
    checkouts: dict[str, tuple[Path, bool]] = {
        "this checkout": (REPO_ROOT, False),
        **({f"{args.against}": (args.against.resolve(), False)} if args.against else {}),
        **({"this checkout, forked": (REPO_ROOT, True)} if args.forked else {}),
    }
    if args.forked:
        preloaded.preloader().start()
        preloading = cpu_seconds(preloaded.preloader().pid or 0)
        print(f"the preloaded interpreter: ready after {preloading:.2f} CPU-s (once per pytest process)")
    figures: dict[str, list[tuple[float, float, float]]] = {name: [] for name in checkouts}
    with tempfile.TemporaryDirectory() as root:
        for number in range(1, args.rounds + 1):
            for name, (checkout, forked) in checkouts.items():
                figures[name].append(one_start(checkout, Path(tempfile.mkdtemp(dir=root)), forked))
                answered, cpu, recording = figures[name][-1]
                print(
                    f"round {number} {name}: answers in {answered:.2f} s ({cpu:.2f} CPU-s), "
                    f"first recording started in {recording:.2f} s",
                    flush=True,
                )
    print(f"load {os.getloadavg()[0]:.1f}; median (range) of {args.rounds}:")
    for name, rows in figures.items():
        print(
            f"  {name}: answers in {summary([row[0] for row in rows])} s, "
            f"{summary([row[1] for row in rows])} CPU-s; first recording "
            f"{summary([row[2] for row in rows])} s"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
