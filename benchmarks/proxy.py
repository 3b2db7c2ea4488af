"""Proxy overhead on GET /pose: the simulator served directly vs the same simulator behind the proxy.

Starts `python -m pendant --no-ui --api-port A` (the "controller") and `python -m pendant.remote.proxy
--robot http://127.0.0.1:A --port B` on free loopback ports, then times GET /pose over keep-alive httpx
clients, alternating blocks so drift on a busy machine hits both sides alike. Target: proxied p50 - direct
p50 <= 1 ms.

    .venv/bin/python benchmarks/proxy.py [--requests 2000]
"""

from __future__ import annotations

import argparse
import os
import signal
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import httpx

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from tests.support.ports import free_port  # noqa: E402

START_TIMEOUT_S = 30.0
WARMUP_REQUESTS = 200
BLOCKS = 10
TARGET_OVERHEAD_MS = 1.0


@contextmanager
def serving(args: list[str], url: str) -> Iterator[None]:
    """Run `python args...` until `url` answers; stop it afterwards."""
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    process = subprocess.Popen([sys.executable, *args], cwd=ROOT, env=env)
    try:
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            if process.poll() is not None:
                raise RuntimeError(f"{args} exited with {process.returncode}")
            try:
                if httpx.get(url, timeout=1.0).status_code == 200:
                    break
            except httpx.HTTPError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError(f"{args} did not answer {url} within {START_TIMEOUT_S} s")
            time.sleep(0.1)
        yield
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=5.0)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def time_gets(client: httpx.Client, url: str, count: int) -> list[float]:
    samples = []
    for _ in range(count):
        started = time.perf_counter()
        response = client.get(url)
        samples.append(time.perf_counter() - started)
        if response.status_code != 200:
            raise RuntimeError(f"GET {url}: {response.status_code} {response.text}")
    return samples


def percentile_ms(samples: list[float], fraction: float) -> float:
    ordered = sorted(samples)
    return 1000.0 * ordered[min(len(ordered) - 1, int(fraction * len(ordered)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--requests", type=int, default=2000, help="timed GET /pose per side")
    args = parser.parse_args()

    sim_port, proxy_port = free_port(), free_port()
    direct_url = f"http://127.0.0.1:{sim_port}/pose"
    proxied_url = f"http://127.0.0.1:{proxy_port}/pose"
    sim = ["-m", "pendant", "--no-ui", "--api-port", str(sim_port)]
    proxy = [
        "-m",
        "pendant.remote.proxy",
        "--robot",
        f"http://127.0.0.1:{sim_port}",
        "--port",
        str(proxy_port),
    ]
    direct_samples: list[float] = []
    proxied_samples: list[float] = []
    with (
        serving(sim, direct_url),
        serving(proxy, proxied_url),
        httpx.Client() as direct,
        httpx.Client() as proxied,
    ):
        time_gets(direct, direct_url, WARMUP_REQUESTS)
        time_gets(proxied, proxied_url, WARMUP_REQUESTS)
        block = max(1, args.requests // BLOCKS)
        for _ in range(BLOCKS):
            direct_samples += time_gets(direct, direct_url, block)
            proxied_samples += time_gets(proxied, proxied_url, block)

    for name, samples in (("direct ", direct_samples), ("proxied", proxied_samples)):
        print(
            f"GET /pose {name}: n={len(samples)} p50={percentile_ms(samples, 0.5):.3f} ms "
            f"p90={percentile_ms(samples, 0.9):.3f} ms p99={percentile_ms(samples, 0.99):.3f} ms "
            f"mean={1000 * statistics.fmean(samples):.3f} ms"
        )
    overhead_ms = percentile_ms(proxied_samples, 0.5) - percentile_ms(direct_samples, 0.5)
    verdict = "OK" if overhead_ms <= TARGET_OVERHEAD_MS else "OVER TARGET"
    print(
        f"proxy overhead (p50 proxied - p50 direct): {overhead_ms:.3f} ms "
        f"(target <= {TARGET_OVERHEAD_MS} ms: {verdict})"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
