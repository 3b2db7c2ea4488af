"""PULSE REST API speed: GET /pose latency over one keep-alive connection, and throughput with 32 connections.

Starts `pendant --no-ui` (as `python -m pendant`) on a free loopback port and measures it from outside:
- p50/p90/p99 latency of GET /pose with one httpx client (one keep-alive connection), after a warm-up, and
  the same over a bare socket (no client library), which shows the server's own share;
- requests/s of GET /pose with 32 connections, by `wrk` when installed (apt-get install wrk), else by an
  asyncio httpx client (which itself costs CPU on this machine, so it reads lower).

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
from tests.api.server import running_pendant

CONNECTIONS = 32
WARMUP_REQUESTS = 500


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
    host, port = base_url.removeprefix("http://").split(":")
    request = f"GET /pose HTTP/1.1\r\nHost: {host}\r\n\r\n".encode()
    with socket.create_connection((host, int(port))) as connection:
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
    length = int(re.search(rb"content-length: *(\d+)", head, re.IGNORECASE).group(1))
    while len(body) < length:
        body += connection.recv(65536)
    return data


def percentiles(times_s: list[float]) -> str:
    quantiles = statistics.quantiles([t * 1000 for t in times_s], n=100)
    return f"p50 {quantiles[49]:.3f} ms   p90 {quantiles[89]:.3f} ms   p99 {quantiles[98]:.3f} ms"


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


async def _throughput_httpx(base_url: str, seconds: float) -> float:
    limits = httpx.Limits(max_connections=CONNECTIONS, max_keepalive_connections=CONNECTIONS)
    async with httpx.AsyncClient(base_url=base_url, limits=limits) as client:
        done = 0
        deadline = time.perf_counter() + seconds

        async def worker() -> None:
            nonlocal done
            while time.perf_counter() < deadline:
                response = await client.get("/pose")
                assert response.status_code == 200
                done += 1

        start = time.perf_counter()
        await asyncio.gather(*(worker() for _ in range(CONNECTIONS)))
        return done / (time.perf_counter() - start)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=5000, help="requests for the latency run")
    parser.add_argument("--seconds", type=float, default=5.0, help="duration of the throughput run")
    args = parser.parse_args()

    with running_pendant() as base_url:
        print(f"GET /pose, 1 keep-alive connection, {args.requests} requests:")
        print(f"  httpx client: {percentiles(single_connection_latency(base_url, args.requests))}")
        print(f"  raw socket:   {percentiles(raw_socket_latency(base_url, args.requests))}")

        if shutil.which("wrk"):
            rate, tool = throughput_wrk(base_url, args.seconds), "wrk -t2"
        else:
            rate, tool = asyncio.run(_throughput_httpx(base_url, args.seconds)), "asyncio httpx"
        print(f"GET /pose, {CONNECTIONS} connections, {args.seconds:g} s ({tool}): {rate:,.0f} requests/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
