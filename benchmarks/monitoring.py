"""Monitoring costs: logging an event (memory only vs. with the SQLite store), the store's write rate, the
dashboard's searches over a large log, a /metrics scrape, and an MCAP recording's size.

Runs in-process on temporary folders (about 20 s):

    .venv/bin/python benchmarks/monitoring.py [--events 100000]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

from fastapi import FastAPI
from fastapi.testclient import TestClient

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pendant.eventlog import EventKind, EventLog  # noqa: E402
from pendant.eventquery import EventQuery  # noqa: E402
from pendant.monitoring import EventStore, PendantMetrics, metrics_router  # noqa: E402
from pendant.sim import FakeClock, SimController  # noqa: E402
from pendant.telemetry import ArmState, Telemetry  # noqa: E402

RECORD_SAMPLES = 5000
SCRAPES = 200
SEARCHES = 20
RECORDING_S = 60.0


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def record_latency(log: EventLog) -> tuple[float, float]:
    times = []
    for i in range(RECORD_SAMPLES):
        t0 = time.perf_counter()
        log.record(EventKind.COMMAND, "API 127.0.0.1 (bench)", f"PUT /pose -> 200 #{i}")
        times.append(time.perf_counter() - t0)
    return statistics.median(times) * 1e6, percentile(times, 0.99) * 1e6


def main() -> int:
    parser = argparse.ArgumentParser()
    parser.add_argument("--events", type=int, default=100_000, help="events in the log searched")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        memory_p50, memory_p99 = record_latency(EventLog())
        store = EventStore(Path(folder) / "a")
        stored_p50, stored_p99 = record_latency(EventLog(store=store))
        store.flush(timeout=60)
        print(f"record(), memory only: p50 {memory_p50:.1f} µs, p99 {memory_p99:.1f} µs")
        print(
            f"record(), with the SQLite store: p50 {stored_p50:.1f} µs, p99 {stored_p99:.1f} µs "
            f"({stored_p50 / memory_p50:.2f}x)"
        )

        store = EventStore(Path(folder) / "b")
        log = EventLog(store=store)
        t0 = time.perf_counter()
        for i in range(args.events):  # a day of a looping program: mostly state changes
            if i % 50 == 0:
                log.record(EventKind.COMMAND, f"browser #{i % 7}", f"Run program #{i}")
            else:
                log.record(EventKind.STATE, "controller", "IDLE → RUNNING" if i % 2 else "RUNNING → IDLE")
        store.flush(timeout=120)
        rate = args.events / (time.perf_counter() - t0)
        size_mb = sum(p.stat().st_size for p in store.folder.iterdir()) / 1e6
        print(f"store: {args.events} events written at {rate:,.0f}/s, {size_mb:.1f} MB on disk")
        for name, query in (
            ("dashboard default (folded, 40 rows)", EventQuery(limit=40, fold=True)),
            ("commands only (40 rows)", EventQuery(kinds=("command",), limit=40)),
            ("text search, no match (40 rows)", EventQuery(text="collision", limit=40)),
        ):
            times = []
            for _ in range(SEARCHES):
                t0 = time.perf_counter()
                store.search(query)
                times.append(time.perf_counter() - t0)
            print(f"search {name}: median {statistics.median(times) * 1e3:.1f} ms")
        store.close()

        clock = FakeClock()
        sim = SimController("pulse75", clock)
        metrics = PendantMetrics(sim, mode="sim", model="pulse75", robot_url=None)
        app = FastAPI()
        app.include_router(metrics_router(metrics))
        client = TestClient(app)
        times = []
        for _ in range(SCRAPES):
            t0 = time.perf_counter()
            body = client.get("/metrics").content
            times.append(time.perf_counter() - t0)
        median_ms = statistics.median(times) * 1e3
        print(f"GET /metrics (simulator, in-process): median {median_ms:.2f} ms, {len(body)} bytes")

        telemetry = Telemetry(sim, now=clock.now, recordings_folder=Path(folder) / "rec")
        telemetry.start_recording()
        for _ in range(int(RECORDING_S * 10)):
            clock.advance(0.1)
            telemetry.sample(ArmState(sim.get_position(), {}, {}, "IDLE"))
        telemetry.stop_recording()
        mcap, csv = telemetry.recordings()[0].files
        print(
            f"recording, one minute at 10 Hz: MCAP {mcap.stat().st_size / 1e3:.0f} kB (zstd), "
            f"CSV {csv.stat().st_size / 1e3:.0f} kB"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
