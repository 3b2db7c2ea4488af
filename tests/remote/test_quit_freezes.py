"""Quitting stops the arm (issue 22): a proxy pendant (`pendant --no-ui --robot URL`) sent SIGTERM or SIGINT
while the arm behind it moves freezes it first and says so; kill -9 cannot, and the arm moves on."""

from __future__ import annotations

import signal
import subprocess
from collections.abc import Iterator

import httpx
import pytest

from tests.support.launchers import STOP_TIMEOUT_S, pendant_process, running_pendant
from tests.support.stop_clients import (
    MOVING_DEG,
    STILL_DEG,
    STILL_WINDOW_S,
    j1_travel,
    ready_to_move,
    start_long_move,
)
from tests.support.waiting import SAFETY_NET_S


@pytest.fixture(scope="module")
def arm_url() -> Iterator[str]:
    """The "real arm": a simulator on the wall clock, outliving the proxies killed in front of it."""
    with running_pendant() as url:
        yield url


@pytest.fixture
def arm(arm_url: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=arm_url, timeout=SAFETY_NET_S) as client:
        ready_to_move(client)
        yield client
        ready_to_move(client)


def _quit_mid_motion(arm: httpx.Client, arm_url: str, how: signal.Signals) -> tuple[float, str]:
    """Start a long PUT /pose through a fresh proxy, send it `how`; how far J1 turns over the next 0.5 s once
    the proxy has exited, and what the proxy printed."""
    with pendant_process("--robot", arm_url) as (process, proxy_url):
        with httpx.Client(base_url=proxy_url, timeout=SAFETY_NET_S) as api:
            start_long_move(api, arm)
        process.send_signal(how)
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            pytest.fail(f"the proxy did not exit on {how.name}")
        travel = j1_travel(arm, STILL_WINDOW_S)
        output = process.stdout.read() if process.stdout else ""
    return travel, output


@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGINT])
def test_a_proxy_told_to_quit_freezes_the_arm_behind_it(
    how: signal.Signals, arm: httpx.Client, arm_url: str
) -> None:
    travel, output = _quit_mid_motion(arm, arm_url, how)
    assert travel < STILL_DEG, f"the arm moved {travel:.3f} deg after the proxy quit on {how.name}"
    assert f"Quitting ({how.name}): PUT /freeze sent" in output


def test_kill_9_cannot_freeze_the_arm(arm: httpx.Client, arm_url: str) -> None:
    """What the docs warn about: SIGKILL ends the process before it can do anything; the motion goes on."""
    travel, output = _quit_mid_motion(arm, arm_url, signal.SIGKILL)
    assert travel > MOVING_DEG
    assert "Quitting" not in output
