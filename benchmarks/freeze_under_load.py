"""Freeze always wins: PUT /freeze latency while clients hammer the API with the heaviest requests they can.

Starts `pendant --no-ui` (as `python -m pendant`) on a free loopback port and sends PUT /freeze every
`--period-ms` over one keep-alive connection (bare socket, so the server is what is measured), through phases:

- idle: nothing else;
- bodies: `--attackers` clients each sending, in a loop, the largest /poses/run body the API accepts (100
  waypoints padded with whitespace up to the limit: parsed, then planned in a worker thread), a
  `--huge-mb` MB body declared up front, and the same streamed chunked (refused at the limit since the fix;
  before it, read whole and parsed);
- connections: the bodies plus `--idle-connections` connections that send nothing and a few slowloris clients
  that trickle a header byte a second.

Target: p99 <= 50 ms in every phase. Run: .venv/bin/python benchmarks/freeze_under_load.py [--seconds 5]
"""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import json
import resource
import socket
import statistics
import sys
import threading
import time
from collections.abc import Coroutine
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.launchers import running_pendant
from tests.support.ports import LOOPBACK

CHUNK = 64 * 1024
RUN_BODY_LIMIT = 128 * 1024  # pendant.api.limits: PUT /poses/run
RUN_WAYPOINTS = 100
SLOWLORIS_CLIENTS = 20
ATTACK_READ_TIMEOUT_S = 10.0
FREEZE_TIMEOUT_S = 10.0
FREEZE = b"PUT /freeze HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\n\r\n"


def max_allowed_run_body() -> bytes:
    """100 small joint moves around home, padded with whitespace (valid JSON) up to the body limit."""
    waypoints = [{"angles": [(i % 10) * 0.5, -90.0, 90.0, -90.0, -90.0, 0.0]} for i in range(RUN_WAYPOINTS)]
    body = json.dumps(waypoints).encode()
    return body + b" " * (RUN_BODY_LIMIT - len(body))


def request_head(path: str, length: int | None) -> bytes:
    size = b"Transfer-Encoding: chunked" if length is None else b"Content-Length: %d" % length
    return b"PUT %s HTTP/1.1\r\nHost: 127.0.0.1\r\n%s\r\n\r\n" % (path.encode(), size)


async def read_response(reader: asyncio.StreamReader) -> None:
    head = await reader.readuntil(b"\r\n\r\n")
    for line in head.split(b"\r\n"):
        if line.lower().startswith(b"content-length:"):
            await reader.readexactly(int(line.split(b":")[1]))


def huge_run_body(size: int) -> bytes:
    """A valid /poses/run body of about `size` bytes: the same pose over and over (as the audit sent)."""
    pose = b'{"angles": [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]}'
    return b"[" + b",".join([pose] * max(1, size // (len(pose) + 1))) + b"]"


async def send_body(port: int, path: str, body: bytes, chunked: bool, stop: asyncio.Event) -> None:
    """Send `body` to `path` in full, whatever the server says meanwhile."""
    reader, writer = await asyncio.open_connection(LOOPBACK, port)
    try:
        writer.write(request_head(path, None if chunked else len(body)))
        for start in range(0, len(body), CHUNK):
            if stop.is_set():
                break
            part = body[start : start + CHUNK]
            writer.write(b"%x\r\n%s\r\n" % (len(part), part) if chunked else part)
            await writer.drain()
        if chunked:
            writer.write(b"0\r\n\r\n")
        await asyncio.wait_for(read_response(reader), ATTACK_READ_TIMEOUT_S)
    finally:
        writer.close()


# What an attacker sees when the server refuses or closes on it: it just tries again.
ATTACK_ERRORS = (OSError, asyncio.IncompleteReadError, TimeoutError, asyncio.LimitOverrunError)


async def huge_bodies(port: int, body: bytes, chunked: bool, stop: asyncio.Event) -> None:
    while not stop.is_set():
        with contextlib.suppress(*ATTACK_ERRORS):
            await send_body(port, "/poses/run?speed=100", body, chunked, stop)
        await asyncio.sleep(0.01)


async def max_allowed_runs(port: int, stop: asyncio.Event) -> None:
    body = max_allowed_run_body()
    while not stop.is_set():
        with contextlib.suppress(*ATTACK_ERRORS):
            reader, writer = await asyncio.open_connection(LOOPBACK, port)
            try:
                while not stop.is_set():
                    writer.write(request_head("/poses/run?speed=100", len(body)) + body)
                    await writer.drain()
                    await asyncio.wait_for(read_response(reader), ATTACK_READ_TIMEOUT_S)
            finally:
                writer.close()


async def idle_connections(port: int, count: int, stop: asyncio.Event) -> None:
    """Keep `count` connections open that never send anything (re-opened when the server closes them)."""
    writers: list[asyncio.StreamWriter] = []
    while not stop.is_set():
        writers = [w for w in writers if not w.is_closing() and not w.transport.is_closing()]
        for _ in range(count - len(writers)):
            with contextlib.suppress(OSError):
                _, writer = await asyncio.open_connection(LOOPBACK, port)
                writers.append(writer)
        await asyncio.sleep(0.5)
    for writer in writers:
        writer.close()


async def slowloris(port: int, stop: asyncio.Event) -> None:
    head = b"GET /pose HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: " + b"a" * 10_000
    while not stop.is_set():
        with contextlib.suppress(OSError):
            _, writer = await asyncio.open_connection(LOOPBACK, port)
            try:
                for byte in head:
                    if stop.is_set():
                        break
                    writer.write(bytes([byte]))
                    await writer.drain()
                    await asyncio.sleep(1.0)
            finally:
                writer.close()


PHASES = {
    "idle": (),
    "runs": ("runs",),
    "huge": ("huge",),
    "bodies": ("runs", "huge"),
    "connections": ("idle", "slowloris"),
    "all": ("runs", "huge", "idle", "slowloris"),
}


def attacks(
    port: int, args: argparse.Namespace, kinds: tuple[str, ...], stop: asyncio.Event
) -> list[Coroutine[Any, Any, None]]:
    huge = huge_run_body(int(args.huge_mb * 1024 * 1024))
    chosen: list[Coroutine[Any, Any, None]] = []
    if "runs" in kinds:
        chosen += [max_allowed_runs(port, stop) for _ in range(args.attackers)]
    if "huge" in kinds:
        chosen += [
            huge_bodies(port, huge, chunked, stop) for chunked in (False, True) for _ in range(args.attackers)
        ]
    if "idle" in kinds:
        chosen.append(idle_connections(port, args.idle_connections, stop))
    if "slowloris" in kinds:
        chosen += [slowloris(port, stop) for _ in range(SLOWLORIS_CLIENTS)]
    return chosen


def run_attacks(port: int, args: argparse.Namespace, kinds: tuple[str, ...], done: threading.Event) -> None:
    async def main() -> None:
        stop = asyncio.Event()
        tasks = [asyncio.ensure_future(attack) for attack in attacks(port, args, kinds, stop)]
        while not done.is_set():
            await asyncio.sleep(0.05)
        stop.set()
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    asyncio.run(main())


class FreezeProbe:
    """PUT /freeze over one keep-alive bare-socket connection (a new one if the server closed it)."""

    def __init__(self, port: int) -> None:
        self.port = port
        self.sock: socket.socket | None = None

    def freeze(self) -> float:
        start = time.perf_counter()
        for attempt in range(2):
            try:
                if self.sock is None:
                    self.sock = socket.create_connection((LOOPBACK, self.port), timeout=FREEZE_TIMEOUT_S)
                self.sock.sendall(FREEZE)
                answer = b""
                while b"\r\n\r\n" not in answer:
                    data = self.sock.recv(4096)
                    if not data:
                        raise ConnectionResetError("closed")
                    answer += data
                if not answer.startswith(b"HTTP/1.1 200"):
                    raise RuntimeError(f"PUT /freeze answered {answer[:40]!r}")
                return time.perf_counter() - start
            except (OSError, ConnectionResetError):
                if self.sock is not None:
                    self.sock.close()
                self.sock = None
                if attempt == 1:
                    raise
        raise AssertionError("unreachable")


def measure(probe: FreezeProbe, seconds: float, period_s: float) -> list[float]:
    """Seconds per PUT /freeze; one that got no answer within FREEZE_TIMEOUT_S counts as that long."""
    times: list[float] = []
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        try:
            times.append(probe.freeze())
        except (OSError, RuntimeError):  # no answer in time, or not 200
            times.append(FREEZE_TIMEOUT_S)
            probe.sock = None
        time.sleep(period_s)
    return times


def report(phase: str, times: list[float]) -> None:
    ms = sorted(t * 1000 for t in times)
    p99 = ms[min(len(ms) - 1, round(0.99 * (len(ms) - 1)))]
    failed = sum(t >= FREEZE_TIMEOUT_S * 1000 for t in ms)
    print(
        f"{phase:12s} PUT /freeze n={len(ms):4d}  p50 {statistics.median(ms):7.2f} ms  "
        f"p99 {p99:7.2f} ms  max {ms[-1]:7.2f} ms  failed or > {FREEZE_TIMEOUT_S:g} s: {failed}",
        flush=True,
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0, help="per phase")
    parser.add_argument(
        "--phases", nargs="+", choices=PHASES, default=["idle", "bodies", "connections", "all"]
    )
    parser.add_argument("--period-ms", type=float, default=20.0)
    parser.add_argument("--attackers", type=int, default=2, help="clients per kind of body")
    parser.add_argument("--huge-mb", type=float, default=10.0)
    parser.add_argument("--idle-connections", type=int, default=1100)
    parser.add_argument(
        "--max-open-files",
        type=int,
        default=1024,
        help="the pendant's open-file limit (1024: the usual default of a login shell or service)",
    )
    args = parser.parse_args()
    _, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # this process holds the idle connections
    with running_pendant(max_open_files=args.max_open_files) as base_url:
        port = int(base_url.rsplit(":", 1)[1])
        probe = FreezeProbe(port)
        measure(probe, 0.5, args.period_ms / 1000)  # warm-up
        for phase in args.phases:
            if not PHASES[phase]:
                report(phase, measure(probe, args.seconds, args.period_ms / 1000))
                continue
            done = threading.Event()
            attackers = threading.Thread(
                target=run_attacks, args=(port, args, PHASES[phase], done), daemon=True
            )
            attackers.start()
            time.sleep(1.0)  # let the load build up
            try:
                report(phase, measure(probe, args.seconds, args.period_ms / 1000))
            finally:
                done.set()
                attackers.join(30)
            time.sleep(1.0)


if __name__ == "__main__":
    main()
