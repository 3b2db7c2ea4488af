"""Big pre-flight bodies and Freeze (issue #32): PUT /freeze latency while program bodies of 1.6-5 MB
arrive at POST /pendant/preflight, and the server's memory over rounds of plan and pre-flight load.

Starts `pendant --no-ui` (as `python -m pendant`, this checkout) on a free loopback port. Phase 1: one
client sends the same big program (N waypoints and N moves, refused: at most 2,000) again and again while
PUT /freeze is sent every `--period-ms` over one bare-socket keep-alive connection; p50/p99/max per size,
and idle first. Phase 2: `--rounds` rounds of `--clients` clients calling POST /pendant/plan and POST
/pendant/preflight (small and 5 MB bodies) for `--round-s`; the server's RSS after each round (and the
pre-flight worker's, a process of its own since the fix).

Target: Freeze p99 <= 50 ms while 5 MB bodies arrive; server RSS flat (+/- 20 MB) over the rounds.
Run: .venv/bin/python benchmarks/preflight_bodies.py [--seconds 6] [--rounds 10]
"""

from __future__ import annotations

import argparse
import json
import socket
import statistics
import sys
import threading
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.launchers import pendant_process
from tests.support.ports import LOOPBACK

FREEZE = b"PUT /freeze HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\n\r\n"
ORIGIN = {"point": {"x": 0.0, "y": 0.0, "z": 0.0}, "rotation": {"roll": 0.0, "pitch": 0.0, "yaw": 0.0}}
SIZES = (10_000, 20_000, 30_000, 36_000)  # waypoints: 1.4 / 2.8 / 4.2 / 5.0 MB (the issue says 5 MB)
SMALL = {
    "schema_version": 2,
    "name": "small",
    "steps": [{"kind": "loop", "times": 50, "body": [{"kind": "output", "port": 1, "level": "HIGH"}]}],
}
PLAN = {"target": {"angles": [60, -90, 90, -90, -90, 0]}}


def big_program(waypoints: int) -> bytes:
    """~140 bytes a waypoint (the audit sent ~165): a table, no recorded positions, a move to each."""
    table = [{"name": f"w{i}", "pose": {"angles": [i % 90, -90, 90, -90, -90, 0]}} for i in range(waypoints)]
    move = {"kind": "move", "motion": "JOINT", "speed": 40.0}
    steps = [{**move, "waypoint": f"w{i}"} for i in range(waypoints)]
    document = {"schema_version": 2, "name": "big", "waypoints": table, "steps": steps}
    return json.dumps(document).encode()


def freeze_latencies_ms(port: int, seconds: float, period_s: float) -> list[float]:
    """PUT /freeze every `period_s` for `seconds` over one keep-alive connection: each answer's latency."""
    times = []
    with socket.create_connection((LOOPBACK, port)) as connection:
        connection.settimeout(30)
        reader = connection.makefile("rb")
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            started = time.perf_counter()
            connection.sendall(FREEZE)
            length = 0
            while (line := reader.readline()) not in (b"\r\n", b""):
                if line.lower().startswith(b"content-length:"):
                    length = int(line.split(b":")[1])
            reader.read(length)
            times.append((time.perf_counter() - started) * 1e3)
            time.sleep(max(0.0, period_s - (time.perf_counter() - started)))
    return times


def summary(times: list[float]) -> str:
    ordered = sorted(times)
    p99 = ordered[min(len(ordered) - 1, int(0.99 * len(ordered)))]
    median = statistics.median(ordered)
    return f"p50 {median:6.1f} ms  p99 {p99:7.1f} ms  max {ordered[-1]:7.1f} ms  (n={len(times)})"


def keep_sending(url: str, body: bytes, stop: threading.Event, answers: list[str]) -> None:
    with httpx.Client(timeout=120) as client:
        while not stop.is_set():
            started = time.perf_counter()
            answer = client.post(f"{url}/pendant/preflight", content=body)
            answers.append(f"{answer.status_code} in {time.perf_counter() - started:.2f} s")


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def children(pid: int) -> list[int]:
    """The processes whose parent is `pid` (the pre-flight worker, multiprocessing's helpers)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            if int(stat.rsplit(")", 1)[1].split()[1]) == pid:
                found.append(int(entry.name))
    return found


def load_round(url: str, clients: int, seconds: float, big: bytes) -> dict[int, int]:
    statuses: dict[int, int] = {}
    lock = threading.Lock()
    end = time.monotonic() + seconds

    def client(number: int) -> None:
        with httpx.Client(base_url=url, timeout=120) as http:
            while time.monotonic() < end:
                if number % 4 == 0:
                    answer = http.post("/pendant/preflight", content=big)
                elif number % 2 == 0:
                    answer = http.post("/pendant/preflight", json=SMALL)
                else:
                    answer = http.post("/pendant/plan", json=PLAN)
                with lock:
                    statuses[answer.status_code] = statuses.get(answer.status_code, 0) + 1

    threads = [threading.Thread(target=client, args=(n,)) for n in range(clients)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return statuses


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=6.0, help="per body size in phase 1")
    parser.add_argument("--period-ms", type=float, default=20.0)
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--round-s", type=float, default=5.0)
    parser.add_argument("--clients", type=int, default=8)
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES), help="waypoints per body")
    args = parser.parse_args()
    with pendant_process() as (process, url):
        # Its log goes to a pipe: read it, or a full pipe stops the server (every refusal is a line).
        threading.Thread(target=lambda: process.stdout and process.stdout.read(), daemon=True).start()
        port = int(url.rsplit(":", 1)[1])
        httpx.post(f"{url}/pendant/preflight", json=SMALL, timeout=120)  # the worker started (since the fix)
        idle = freeze_latencies_ms(port, args.seconds, args.period_ms / 1e3)
        print(f"{'idle':<22}{summary(idle)}")
        for size in args.sizes:
            body = big_program(size)
            stop, answers = threading.Event(), []
            sender = threading.Thread(target=keep_sending, args=(url, body, stop, answers))
            sender.start()
            times = freeze_latencies_ms(port, args.seconds, args.period_ms / 1e3)
            stop.set()
            sender.join()
            label = f"{size:,} wp ({len(body) / 1e6:.1f} MB)"
            print(f"{label:<22}{summary(times)}  refusals: {', '.join(answers[:3])}")
        big = big_program(36_000)  # 5.0 MB
        print(f"RSS start: server {rss_mb(process.pid):.0f} MB")
        for number in range(1, args.rounds + 1):
            statuses = load_round(url, args.clients, args.round_s, big)
            worker = ", ".join(f"worker {rss_mb(pid):.0f} MB" for pid in children(process.pid))
            print(f"round {number:2d}: server {rss_mb(process.pid):.0f} MB {worker}  answers {statuses}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
