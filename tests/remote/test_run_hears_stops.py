"""`pendant run --robot URL` against a pendant's API: a stop that another client sends to that pendant while
the arm stands still (a wait, a gripper step) ends the run there. The runner exits 1 with the cause on
stderr, and the arm stays at the first waypoint instead of going on to the second. Real processes: a
`pendant --no-ui`, the `pendant run` child, and the stop sent by the `curl` binary or by Python's urllib."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from tests.support import preloaded
from tests.support.launchers import REPO_ROOT, child_env, running_pendant
from tests.support.programs import a_to_b_file
from tests.support.waiting import SAFETY_NET_S

pytestmark = pytest.mark.slow

A_DEG = [40.0, -90.0, 90.0, -90.0, -90.0, 0.0]
B_DEG = [-40.0, -90.0, 90.0, -90.0, -90.0, 0.0]
HOME_DEG = [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]
STILL_TOL_DEG = 0.01
HELD_S = 3.0  # the arm is watched this long after the runner exits: it must not go on to B
RUN_TIMEOUT_S = 60.0
POLL_S = 0.02

STEPS = {
    "wait": {"kind": "wait", "ms": 20_000},
    "gripper": {"kind": "gripper", "action": "close", "timeout_ms": 20_000},
}


def freeze_by_curl(url: str) -> None:
    curl = shutil.which("curl")
    assert curl is not None, "the curl binary is part of the test set-up"
    subprocess.run([curl, "-s", "-X", "PUT", f"{url}/freeze"], check=True, timeout=SAFETY_NET_S)


def protective_stop_by_urllib(url: str) -> None:
    with urllib.request.urlopen(
        urllib.request.Request(f"{url}/stop", method="POST"), timeout=SAFETY_NET_S
    ) as answer:
        assert answer.status == 200


STOPS = {
    "PUT /freeze (curl)": (freeze_by_curl, "Freeze from the API (127.0.0.1)"),
    "POST /stop (urllib)": (protective_stop_by_urllib, "Protective stop from the API (127.0.0.1)"),
}


@pytest.fixture(scope="module")
def api_url() -> Iterator[str]:
    with running_pendant() as url:
        yield url


def pose(api: httpx.Client) -> np.ndarray:
    return np.array(api.get("/pose").json()["angles"], dtype=float)


@pytest.mark.parametrize("stop", list(STOPS))
@pytest.mark.parametrize("step", list(STEPS))
def test_a_stop_sent_to_the_pendant_during_a_still_step_ends_pendant_run(
    api_url: str, tmp_path: Path, step: str, stop: str
) -> None:
    api = httpx.Client(base_url=api_url, timeout=SAFETY_NET_S)
    api.put("/recover")  # the last case's protective stop
    api.put("/pose", json={"angles": HOME_DEG}).raise_for_status()
    saved = tmp_path / "stopped.json"
    saved.write_text(json.dumps(a_to_b_file("stopped", A_DEG, B_DEG, STEPS[step])))
    runner = preloaded.popen(
        [sys.executable, "-m", "pendant", "run", str(saved), "--robot", api_url],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=child_env(),
    )
    try:
        assert runner.stdout is not None
        deadline = time.monotonic() + RUN_TIMEOUT_S
        while "step 2/3" not in runner.stdout.readline():  # the runner prints each step as it reaches it
            assert runner.poll() is None and time.monotonic() < deadline, "the run never reached step 2"
        time.sleep(0.5)  # well inside the 20 s step, the arm standing at A
        send, cause = STOPS[stop]
        send(api_url)
        _, err = runner.communicate(timeout=RUN_TIMEOUT_S)
    finally:
        if runner.poll() is None:
            runner.kill()
            runner.wait()

    assert runner.returncode == 1, err
    assert f"Stopped at step 2 by {cause}" in err
    held = pose(api)
    np.testing.assert_allclose(held, A_DEG, atol=STILL_TOL_DEG)
    time.sleep(HELD_S)
    np.testing.assert_allclose(pose(api), held, atol=STILL_TOL_DEG)  # not on its way to B
