"""PULSE REST API speed: GET /pose latency over one keep-alive connection, and throughput with 32 connections.

Starts `pendant --no-ui` (as `python -m pendant`) on a free loopback port and measures it from outside:
- p50/p90/p99 latency of GET /pose with one httpx client (one keep-alive connection), after a warm-up, and
  the same over a bare socket (no client library), which shows the server's own share;
- the same bare-socket latency while the arm is moving (a slow PUT /pose first), when the pose is evaluated
  on the trajectory rather than read at rest;
- requests/s of GET /pose with 32 keep-alive connections, by `wrk` when installed (apt-get install wrk), else
  by an asyncio load generator on bare sockets (no HTTP client library, so the server is what is measured;
  it shares the CPU with the server, so it may still read a little lower than wrk).

Targets: p50 <= 0.5 ms; >= 3,000 requests/s with 32 connections.
Run: .venv/bin/python benchmarks/api.py [--requests 5000] [--seconds 5]
"""

from __future__ import annotations

import argparse
import asyncio
import re
import shutil
import socket
import statistics
import subprocess
import sys
import time
from pathlib import Path

import httpx

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.support.launchers import running_pendant
from tests.support.ports import LOOPBACK

CONNECTIONS = 32
WARMUP_REQUESTS = 500
# A far, slow move: at 5 % it lasts far longer than the latency run, so every sample sees a moving arm.
MOVING_TARGET_DEG = [120.0, -30.0, 30.0, -120.0, -30.0, 120.0]
MOVING_SPEED_PERCENT = 5
# The load run stops this long after its duration at the latest, so a stuck connection cannot hang it.
LOAD_GRACE_S = 5.0
CONTENT_LENGTH = re.compile(rb"content-length: *(\d+)", re.IGNORECASE)


def split_url(base_url: str) -> tuple[str, int]:
    host, port = base_url.removeprefix("http://").split(":")
    if host != LOOPBACK:  # the load generator must never point at anything but this machine
        raise ValueError(f"benchmark talks only to {LOOPBACK}, not {host}")
    return host, int(port)


def single_connection_latency(base_url: str, requests: int) -> list[float]:
    """Seconds per GET /pose, one after another over one keep-alive connection."""
    with httpx.Client(base_url=base_url) as client:
        for _ in range(WARMUP_REQUESTS):
            client.get("/pose")
        times = []
        for _ in range(requests):
            start = time.perf_counter()
            response = client.get("/pose")
            times.append(time.perf_counter() - start)
            assert response.status_code == 200
    return times


def raw_socket_latency(base_url: str, requests: int) -> list[float]:
    """Seconds per GET /pose over one keep-alive socket with no HTTP client library: the server's share."""
    host, port = split_url(base_url)
    request = f"GET /pose HTTP/1.1\r\nHost: {host}\r\n\r\n".encode()
    with socket.create_connection((host, port)) as connection:
        connection.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        times = []
        for i in range(WARMUP_REQUESTS + requests):
            start = time.perf_counter()
            connection.sendall(request)
            response = read_response(connection)
            if i >= WARMUP_REQUESTS:
                times.append(time.perf_counter() - start)
            assert response.startswith(b"HTTP/1.1 200"), response
    return times


def read_response(connection: socket.socket) -> bytes:
    """One whole HTTP/1.1 response with a Content-Length (the server may send head and body apart)."""
    data = b""
    while b"\r\n\r\n" not in data:
        data += connection.recv(65536)
    head, _, body = data.partition(b"\r\n\r\n")
    length = int(CONTENT_LENGTH.search(head).group(1))
    while len(body) < length:
        body += connection.recv(65536)
    return data


def moving_latency(base_url: str, requests: int) -> list[float]:
    """Bare-socket GET /pose latency while a slow move runs; fails if the arm stopped before the end."""
    with httpx.Client(base_url=base_url) as client:
        client.put("/pose", params={"speed": MOVING_SPEED_PERCENT}, json={"angles": MOVING_TARGET_DEG})
        times = raw_socket_latency(base_url, requests)
        status = client.get("/status/motion").json()
    if status != "RUNNING":
        raise RuntimeError(f"the arm was {status} at the end of the run: make the move longer")
    return times


def p50(times_s: list[float]) -> str:
    quantiles = statistics.quantiles([t * 1000 for t in times_s], n=100)
    return f"p50 {quantiles[49]:.3f} ms   (p90 {quantiles[89]:.3f} ms, p99 {quantiles[98]:.3f} ms)"


def throughput_wrk(base_url: str, seconds: float) -> float:
    output = subprocess.run(
        ["wrk", "-t2", f"-c{CONNECTIONS}", f"-d{seconds:g}s", f"{base_url}/pose"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    if "Non-2xx" in output:
        raise RuntimeError(f"wrk saw errors:\n{output}")
    match = re.search(r"Requests/sec:\s+([\d.]+)", output)
    assert match, output
    return float(match.group(1))


async def _throughput_sockets(base_url: str, seconds: float) -> float:
    """GET /pose requests/s over CONNECTIONS keep-alive sockets, one request in flight on each (as wrk)."""
    host, port = split_url(base_url)
    request = f"GET /pose HTTP/1.1\r\nHost: {host}\r\n\r\n".encode()
    # Connect all first, so connection setup is not counted in the rate.
    connections = await asyncio.gather(*(asyncio.open_connection(host, port) for _ in range(CONNECTIONS)))
    done = 0

    async def worker(reader: asyncio.StreamReader, writer: asyncio.StreamWriter, deadline: float) -> None:
        nonlocal done
        while time.perf_counter() < deadline:
            writer.write(request)
            head = await reader.readuntil(b"\r\n\r\n")
            if not head.startswith(b"HTTP/1.1 200"):
                raise RuntimeError(f"GET /pose answered {head!r}")
            await reader.readexactly(int(CONTENT_LENGTH.search(head).group(1)))
            done += 1

    try:
        start = time.perf_counter()
        workers = (worker(reader, writer, start + seconds) for reader, writer in connections)
        await asyncio.wait_for(asyncio.gather(*workers), seconds + LOAD_GRACE_S)
        return done / (time.perf_counter() - start)
    finally:
        for _, writer in connections:
            writer.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=5000, help="requests for each latency run")
    parser.add_argument("--seconds", type=float, default=5.0, help="duration of the throughput run")
    args = parser.parse_args()

    with running_pendant() as base_url:
        runs = f"{args.requests} requests after {WARMUP_REQUESTS} warm-up"
        print(f"GET /pose latency, 1 keep-alive connection, {runs}:")
        print(f"  at rest, httpx client: {p50(single_connection_latency(base_url, args.requests))}")
        print(f"  at rest, raw socket:   {p50(raw_socket_latency(base_url, args.requests))}")

        # Throughput at rest, before the move below, so it compares with earlier runs.
        if shutil.which("wrk"):
            rate, tool = throughput_wrk(base_url, args.seconds), "wrk -t2"
        else:
            rate, tool = asyncio.run(_throughput_sockets(base_url, args.seconds)), "asyncio raw sockets"

        print(f"  moving,  raw socket:   {p50(moving_latency(base_url, args.requests))}")
        load = f"{CONNECTIONS} connections, {args.seconds:g} s, {tool}"
        print(f"GET /pose throughput, {load}: {rate:,.0f} requests/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
