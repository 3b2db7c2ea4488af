"""Waiting for a real process on a real clock: no fake clock can stand in for these waits."""

from __future__ import annotations

import time
from collections.abc import Callable

import httpx

DEFAULT_TIMEOUT_S = 60.0
# A request's time-out where the answer is not what is measured: it only catches a hang (a test in the idle
# class beside the timed pass can get no CPU for seconds; docs/development.md).
SAFETY_NET_S = 30.0
POLL_S = 0.05


def wait_until(
    ready: Callable[[], bool],
    timeout_s: float = DEFAULT_TIMEOUT_S,
    what: str | Callable[[], str] = "it",
    poll_s: float = POLL_S,
) -> None:
    """Poll `ready` until it holds (an HTTP error counts as "not yet"); TimeoutError naming `what` after
    `timeout_s` (a callable: read then, to say how things stood)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            if ready():
                return
        except httpx.HTTPError:
            pass
        time.sleep(poll_s)
    said = what() if callable(what) else what
    raise TimeoutError(f"{said} did not happen within {timeout_s} s")


def answers(url: str) -> bool:
    """Anything at `url` answers HTTP at all."""
    httpx.get(url, timeout=1.0)
    return True


MOTION_TIMEOUT_S = 30.0


def wait_idle(api: httpx.Client, timeout_s: float = MOTION_TIMEOUT_S) -> None:
    """Poll GET /status/motion until the arm is IDLE; AssertionError after `timeout_s`."""
    deadline = time.monotonic() + timeout_s
    while api.get("/status/motion").text.strip('"') != "IDLE":
        assert time.monotonic() < deadline, "the arm did not come to rest"
        time.sleep(POLL_S)
