"""Free loopback ports, and waiting for something to listen on one."""

from __future__ import annotations

import socket
import time

LOOPBACK = "127.0.0.1"
WAIT_STEP_S = 0.05


def free_port() -> int:
    """A TCP port nobody listens on right now (the OS picks it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind((LOOPBACK, 0))
        return int(probe.getsockname()[1])


def wait_for_port(port: int, timeout_s: float) -> None:
    """Return once something accepts connections on `port`; fail after `timeout_s`."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            with socket.create_connection((LOOPBACK, port), timeout=WAIT_STEP_S):
                return
        except OSError:
            time.sleep(WAIT_STEP_S)
    raise TimeoutError(f"nothing listens on {LOOPBACK}:{port} after {timeout_s} s")
