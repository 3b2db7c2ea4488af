"""Real clients for the stop tests: the `curl` binary and Python's urllib, each in a subprocess, and a watch
on the arm's first joint (how a user sees that it moves, or stays still)."""

from __future__ import annotations

import subprocess
import sys
import time

import httpx

from tests.support.waiting import SAFETY_NET_S, wait_until

CLIENT_TIMEOUT_S = SAFETY_NET_S
FAR_POSE = [60.0, -90.0, 90.0, -90.0, -90.0, 0.0]
HOME_POSE = [-60.0, -90.0, 90.0, -90.0, -90.0, 0.0]
SLOW = {"speed": 5}  # ~6 deg/s on J1: a move of 120 degrees lasts many seconds
MOVING_DEG = 0.2  # J1 has turned at least this much once a motion is under way
# A starved client (the pass behind the timed one, nice 19) may see its first samples seconds apart: a
# started move is waited for this long at most, and returns as soon as J1 has turned MOVING_DEG.
MOVE_START_TIMEOUT_S = 30.0
STILL_WINDOW_S = 0.5
STILL_DEG = 0.01  # a frozen arm's J1 does not drift more than this over STILL_WINDOW_S
SETTLE_DEG = 0.5  # a move counts as arrived within this of its target


def curl(*args: str) -> tuple[int, str]:
    """`curl -s ARGS`: (status, body) as the binary reports them."""
    done = subprocess.run(
        ["curl", "-s", "--max-time", f"{CLIENT_TIMEOUT_S:g}", "-w", "\n%{http_code}", *args],
        capture_output=True,
        text=True,
        timeout=CLIENT_TIMEOUT_S + 5,
        check=True,
    )
    body, _, status = done.stdout.rpartition("\n")
    return int(status), body


_URLLIB = f"""
import sys, urllib.request, urllib.error
method, url, data, content_type = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4]
request = urllib.request.Request(url, method=method, data=None if data == "-" else data.encode())
if content_type != "-":
    request.add_header("Content-Type", content_type)
try:
    with urllib.request.urlopen(request, timeout={CLIENT_TIMEOUT_S:g}) as answer:
        print(answer.status); print(answer.read().decode())
except urllib.error.HTTPError as error:
    print(error.code); print(error.read().decode())
"""


def urllib_request(
    method: str, url: str, data: str | None = "", content_type: str | None = None
) -> tuple[int, str]:
    """Python's urllib in a fresh interpreter: `Request(url, method=..., data=...)` as a script writes it
    (urllib labels any data form-encoded unless told otherwise). `data=None`: no body at all."""
    done = subprocess.run(
        [sys.executable, "-c", _URLLIB, method, url, "-" if data is None else data, content_type or "-"],
        capture_output=True,
        text=True,
        timeout=CLIENT_TIMEOUT_S + 5,
        check=True,
    )
    status, _, body = done.stdout.partition("\n")
    return int(status), body.strip()


def j1(arm: httpx.Client) -> float:
    return float(arm.get("/pose").json()["angles"][0])


def j1_travel(arm: httpx.Client, window_s: float) -> float:
    """How far J1 turns over `window_s`, sampled every 50 ms (the largest distance from the first sample)."""
    first = j1(arm)
    travel = 0.0
    deadline = time.monotonic() + window_s
    while time.monotonic() < deadline:
        time.sleep(0.05)
        travel = max(travel, abs(j1(arm) - first))
    return travel


def start_long_move(api: httpx.Client, arm: httpx.Client) -> None:
    """PUT /pose to the far side of J1, slowly, through `api`; returns once `arm` is seen moving."""
    target = FAR_POSE if j1(arm) < 0 else HOME_POSE
    answer = api.put("/pose", params=SLOW, json={"angles": target})
    assert answer.status_code == 200, answer.text
    first = j1(arm)
    wait_until(lambda: abs(j1(arm) - first) > MOVING_DEG, MOVE_START_TIMEOUT_S, "the move's start")


def ready_to_move(api: httpx.Client) -> None:
    """Out of a stop (PUT /recover is the operator's way) or free drive (PUT /freeze), back to IDLE."""
    api.put("/recover")
    api.put("/freeze")
    assert api.get("/status/motion").text == '"IDLE"'
