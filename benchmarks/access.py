"""The access guard's cost and effect: how many wrong tokens a guesser gets answered per second, and what the
Host check costs a read.

Measured from outside, on free loopback ports:
- `pendant --no-ui --token T`: wrong tokens checked per second while 32 connections hammer `PUT /relax` for a
  few seconds (before the guard slowed them: about 1,090/s), and the statuses answered;
- `GET /pose` over one bare keep-alive socket, side by side: the simulator's API without the guard and with
  it (Host check, token, Remote control), each in its own process, in alternating rounds.

Run: .venv/bin/python benchmarks/access.py [--seconds 5]
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import contextlib
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from benchmarks.api import raw_socket_latency, split_url
from tests.support.launchers import running_pendant
from tests.support.ports import free_port
from tests.support.waiting import answers, wait_until

ROUNDS = 3

TOKEN = "benchmark-token-0123456789abcdef"
CONNECTIONS = 32
LATENCY_REQUESTS = 3000
GRACE_S = 15.0  # a guess may wait for its turn up to the guard's 10 s


async def _guesser(host: str, port: int, until: float, statuses: collections.Counter[int]) -> None:
    reader, writer = await asyncio.open_connection(host, port)
    try:
        i = 0
        while time.monotonic() < until:
            request = (
                f"PUT /relax HTTP/1.1\r\nHost: {host}\r\nX-Pendant-Token: guess-{i}\r\n"
                "Content-Length: 0\r\n\r\n"
            ).encode()
            writer.write(request)
            head = await reader.readuntil(b"\r\n\r\n")
            length = int(head.lower().split(b"content-length:")[1].split(b"\r\n")[0])
            await reader.readexactly(length)
            statuses[int(head.split(b" ", 2)[1])] += 1
            i += 1
    finally:
        writer.close()


async def guesses_per_second(base_url: str, seconds: float) -> tuple[float, collections.Counter[int]]:
    host, port = split_url(base_url)
    statuses: collections.Counter[int] = collections.Counter()
    started = time.monotonic()
    until = started + seconds
    tasks = [_guesser(host, port, until, statuses) for _ in range(CONNECTIONS)]
    await asyncio.wait_for(asyncio.gather(*tasks), seconds + GRACE_S)
    return sum(statuses.values()) / (time.monotonic() - started), statuses


def serve(guarded: bool, port: int) -> None:
    """The simulator's API alone, with or without the guard (run in a process of its own)."""
    import uvicorn

    from pendant.access.http_guard import AccessRules
    from pendant.access.origin import OriginPolicy
    from pendant.access.remote import RemoteControl
    from pendant.api import create_app
    from pendant.sim import MonotonicClock, SimController

    sim = SimController("pulse75", MonotonicClock())
    access = AccessRules(token=TOKEN, origins=OriginPolicy("127.0.0.1"), remote=RemoteControl(True))
    app = create_app(sim, access=access) if guarded else create_app(sim)
    uvicorn.run(app, host="127.0.0.1", port=port, log_level="warning", access_log=False)


@contextlib.contextmanager
def served(guarded: bool) -> Iterator[str]:
    port = free_port()
    flag = "--serve-guarded" if guarded else "--serve-plain"
    process = subprocess.Popen([sys.executable, __file__, flag, str(port)])
    url = f"http://127.0.0.1:{port}"
    try:
        wait_until(lambda: answers(f"{url}/pose"), 60.0, "the API")
        yield url
    finally:
        process.terminate()
        process.wait(10)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--serve-plain", type=int, metavar="PORT", help=argparse.SUPPRESS)
    parser.add_argument("--serve-guarded", type=int, metavar="PORT", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve_plain or args.serve_guarded:
        serve(bool(args.serve_guarded), args.serve_guarded or args.serve_plain)
        return 0
    medians: dict[bool, list[float]] = {False: [], True: []}
    with served(False) as plain, served(True) as guarded:
        for _ in range(ROUNDS):
            for is_guarded, url in ((False, plain), (True, guarded)):
                medians[is_guarded].append(statistics.median(raw_socket_latency(url, LATENCY_REQUESTS)))
    plain_ms = statistics.median(medians[False]) * 1000
    guarded_ms = statistics.median(medians[True]) * 1000
    print(
        f"GET /pose, one bare socket, p50: {plain_ms:.3f} ms without the guard, {guarded_ms:.3f} ms with it "
        f"(ratio {guarded_ms / plain_ms:.2f})"
    )
    with running_pendant("--token", TOKEN) as url:
        started = time.monotonic()
        rate, statuses = asyncio.run(guesses_per_second(url, args.seconds))
        elapsed = time.monotonic() - started
        print(
            f"wrong tokens checked: {statuses[403]} in {elapsed:.1f} s ({statuses[403] / elapsed:.1f}/s); "
            f"answers {rate:.0f}/s from {CONNECTIONS} connections"
        )
        print("  statuses: " + ", ".join(f"{status} x{count}" for status, count in sorted(statuses.items())))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
