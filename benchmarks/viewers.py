"""Many viewers: N headless browsers watch a moving arm; how often does each see the state, at what CPU cost.

A real `pendant` process (simulator, UI and API on loopback) and N websocket clients speaking viser's
protocol (msgpack over websockets, zstd-compressed windows): each announces a camera, as a browser does on
connecting, then counts the state updates it receives, i.e. the TCP frame's pose (one per refresh tick while
the arm moves) and the GUI updates (status, dashboard). The arm moves the whole time: one slow blended
PUT /poses/run back and forth through the API. The pendant's CPU is read from /proc over the measurement
window (all its threads).

Targets: state to every viewer at >= 30 Hz (no viewer below 25 Hz), the pendant within one core.

Run: .venv/bin/python benchmarks/viewers.py [--viewers 20] [--seconds 10]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.headless_viewer import ViewerCounts, viewer
from tests.support.ports import free_port
from tests.support.waiting import answers, wait_until

START_TIMEOUT_S = 60.0
WARM_UP_S = 3.0
POSES = ([60.0, -70.0, 40.0, -90.0, -90.0, 30.0], [-60.0, -100.0, -30.0, -80.0, -90.0, -30.0])
SPEED_PERCENT = 4.0  # slow: one leg takes several seconds
LEGS_PER_RUN = 10  # longer than any measurement window


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process (all its threads), from /proc."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def keep_moving(api: str, stop: threading.Event) -> None:
    """Slow joint motion back and forth without a stop: one blended /poses/run through many legs (the
    pendant sends nothing while the arm is at rest, so a pause between moves would count as lost updates)."""
    legs = [{"angles": POSES[leg % 2]} for leg in range(LEGS_PER_RUN)]
    with httpx.Client(base_url=api, timeout=5.0) as client:
        while not stop.is_set():
            if client.get("/status/motion").text.strip('"') != "RUNNING":
                client.put("/poses/run", params={"speed": SPEED_PERCENT}, json=legs)
            stop.wait(0.1)


async def measure(
    ui_port: int, n_viewers: int, seconds: float, pid: int
) -> tuple[list[ViewerCounts], float, float, float]:
    """Per-viewer counts over the window, the pendant's CPU (cores), this process's CPU, the window (s)."""
    stop = asyncio.Event()
    counts = [ViewerCounts() for _ in range(n_viewers)]
    tasks = [asyncio.create_task(viewer(f"ws://127.0.0.1:{ui_port}/", c, stop)) for c in counts]
    await asyncio.sleep(WARM_UP_S)
    t0, cpu0, own0 = time.monotonic(), cpu_seconds(pid), cpu_seconds(os.getpid())
    await asyncio.sleep(seconds)
    t1, cpu1, own1 = time.monotonic(), cpu_seconds(pid), cpu_seconds(os.getpid())
    stop.set()
    await asyncio.gather(*tasks)
    rates = [
        ViewerCounts([t for t in c.state_times if t0 <= t < t1], c.gui_updates, c.bytes_received)
        for c in counts
    ]
    return rates, (cpu1 - cpu0) / (t1 - t0), (own1 - own0) / (t1 - t0), t1 - t0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--viewers", type=int, default=20)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()

    ui_port, api_port = free_port(), free_port()
    api = f"http://127.0.0.1:{api_port}"
    process = subprocess.Popen(
        [sys.executable, "-m", "pendant", "--ui-port", str(ui_port), "--api-port", str(api_port)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        cwd=Path(__file__).resolve().parents[1],
    )
    stop_moving = threading.Event()
    try:
        wait_until(lambda: answers(f"{api}/pose"), START_TIMEOUT_S, what="the API answering")
        wait_until(
            lambda: answers(f"http://127.0.0.1:{ui_port}/"), START_TIMEOUT_S, what="the page answering"
        )
        mover = threading.Thread(target=keep_moving, args=(api, stop_moving), daemon=True)
        mover.start()
        idle_cpu0, idle_t0 = cpu_seconds(process.pid), time.monotonic()
        time.sleep(2.0)
        idle_cpu = (cpu_seconds(process.pid) - idle_cpu0) / (time.monotonic() - idle_t0)
        counts, cpu_cores, client_cores, window = asyncio.run(
            measure(ui_port, args.viewers, args.seconds, process.pid)
        )
        load = os.getloadavg()[0]
    finally:
        stop_moving.set()
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()

    rates = [len(c.state_times) / window for c in counts]
    print(
        f"{args.viewers} viewers, arm moving, measured over {window:.1f} s (after {WARM_UP_S:.0f} s warm-up)"
    )
    print(f"pendant CPU, arm moving, no viewers: {idle_cpu:.2f} cores")
    print(f"pendant CPU with {args.viewers} viewers:    {cpu_cores:.2f} cores  (target <= 1.00)")
    print(
        f"the {args.viewers} headless viewers themselves: {client_cores:.2f} cores; load average {load:.1f} "
        f"on {os.cpu_count()} cores"
    )
    print(
        f"state updates per viewer (Hz): min {min(rates):.1f}  median {statistics.median(rates):.1f}  "
        f"max {max(rates):.1f}  (target >= 30, none below 25)"
    )
    print("per viewer (Hz): " + " ".join(f"{r:.1f}" for r in rates))
    gui = [c.gui_updates / (window + WARM_UP_S) for c in counts]
    kib = [c.bytes_received / 1024 / (window + WARM_UP_S) for c in counts]
    print(
        f"GUI updates per viewer: ~{statistics.median(gui):.0f}/s; "
        f"traffic ~{statistics.median(kib):.0f} KiB/s each"
    )
    verdict = max(cpu_cores, 0) <= 1.0 and min(rates) >= 25.0
    print("PASS" if verdict else "MISS")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
