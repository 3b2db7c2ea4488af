"""Start `pendant --no-ui` (as `python -m pendant`) on a free loopback port, wait for it, stop it."""

from __future__ import annotations

import contextlib
import resource
import socket
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import httpx

REPO_ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 60.0
STOP_TIMEOUT_S = 10.0
LOOPBACK = "127.0.0.1"


def wait_until(ready: Callable[[], bool], timeout_s: float = START_TIMEOUT_S, what: str = "it") -> None:
    """Poll `ready` until it holds (an HTTP error counts as "not yet"): a real process on a real clock."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            if ready():
                return
        except httpx.HTTPError:
            pass
        time.sleep(0.05)
    raise TimeoutError(f"{what} did not happen within {timeout_s} s")


def answers(url: str) -> bool:
    """Anything at `url` answers HTTP at all."""
    httpx.get(url, timeout=1.0)
    return True


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind((LOOPBACK, 0))
        return int(probe.getsockname()[1])


@contextlib.contextmanager
def running_pendant(*extra_args: str, max_open_files: int | None = None) -> Iterator[str]:
    """The base URL of a freshly started `pendant --no-ui`; the process is stopped on exit.

    `max_open_files`: the process's open-file limit (soft and hard), as a service or shell might set it."""
    with pendant_process(*extra_args, max_open_files=max_open_files) as (_, base_url):
        yield base_url


@contextlib.contextmanager
def pendant_process(
    *extra_args: str, max_open_files: int | None = None
) -> Iterator[tuple[subprocess.Popen[str], str]]:
    """running_pendant(), also giving the process (to read its memory, say)."""
    port = free_port()
    command = [sys.executable, "-m", "pendant", "--no-ui", "--host", LOOPBACK, "--api-port", str(port)]
    process = subprocess.Popen(
        [*command, *extra_args],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        preexec_fn=None if max_open_files is None else lambda: _limit_open_files(max_open_files),
    )
    base_url = f"http://{LOOPBACK}:{port}"
    try:
        _wait_until_serving(process, base_url)
        yield process, base_url
    finally:
        process.terminate()
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(STOP_TIMEOUT_S)
        if process.stdout is not None:
            process.stdout.close()


def _limit_open_files(count: int) -> None:
    resource.setrlimit(resource.RLIMIT_NOFILE, (count, count))


def _wait_until_serving(process: subprocess.Popen[str], base_url: str) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    announced = process.stdout.readline() if process.stdout else ""  # printed before the server starts
    if base_url not in announced:
        raise RuntimeError(f"pendant did not announce {base_url}, it said: {announced!r}")
    while time.monotonic() < deadline:
        if process.poll() is not None:
            output = process.stdout.read() if process.stdout else ""
            raise RuntimeError(f"pendant exited with {process.returncode}:\n{output}")
        try:
            if httpx.get(f"{base_url}/robot/id", timeout=1.0).status_code == 200:
                return
        except httpx.TransportError:
            pass
        time.sleep(0.05)  # polling a real process starting up: no fake clock can stand in for this wait
    raise RuntimeError(f"pendant did not answer on {base_url} within {START_TIMEOUT_S} s")
