"""Every script in examples/ run as a user runs it (a subprocess, PULSE_URL pointing at a real `pendant
--no-ui` on loopback), checked by what it prints and by where it left the arm."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import pytest

from tests.support.launchers import REPO_ROOT, running_pendant
from tests.support.waiting import SAFETY_NET_S

EXAMPLES = REPO_ROOT / "examples"
RUN_TIMEOUT_S = 120.0
ANGLE_TOL_DEG = 1e-6
POS_TOL_M = 1e-6


@pytest.fixture(scope="module")
def served() -> Iterator[str]:
    """One simulator for the module (10x real time); each test starts from power-on (PUT /sim/reset)."""
    with running_pendant("--time-scale", "10") as url:
        yield url


@pytest.fixture
def url(served: str) -> str:
    httpx.put(f"{served}/sim/reset", timeout=SAFETY_NET_S).raise_for_status()
    return served


def run(url: str, *command: str) -> str:
    """Run `command` in the checkout with PULSE_URL set and this venv's tools first on PATH; its stdout."""
    bin_dir = str(Path(sys.executable).parent)
    env = {**os.environ, "PULSE_URL": url, "PATH": bin_dir + os.pathsep + os.environ.get("PATH", "")}
    done = subprocess.run(
        command, cwd=REPO_ROOT, env=env, capture_output=True, text=True, timeout=RUN_TIMEOUT_S, check=False
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def angles(url: str) -> list[float]:
    return httpx.get(f"{url}/pose", timeout=30.0).json()["angles"]


def test_curl_moves_j1_and_reports_the_pose(url: str) -> None:
    out = run(url, "sh", "examples/move.sh")
    assert 'status: "IDLE"' in out
    printed = json.loads(out.split("pose: ", 1)[1])["angles"]
    assert printed == pytest.approx([30, -90, 90, -90, -90, 0], abs=ANGLE_TOL_DEG)
    assert angles(url) == pytest.approx(printed, abs=ANGLE_TOL_DEG)


def test_plain_python_reaches_the_pose_it_asked_for(url: str) -> None:
    out = run(url, sys.executable, "examples/move_urllib.py")
    assert out.strip() == "arrived at -30.00 -80.00 80.00 -90.00 -90.00 15.00"
    assert angles(url) == pytest.approx([-30, -80, 80, -90, -90, 15], abs=ANGLE_TOL_DEG)


def test_httpx_raises_the_tool_5_cm_in_a_line(url: str) -> None:
    before = httpx.get(f"{url}/position", timeout=30.0).json()
    out = run(url, sys.executable, "examples/line_httpx.py", url)
    after = httpx.get(f"{url}/position", timeout=30.0).json()
    assert after["point"]["z"] == pytest.approx(before["point"]["z"] + 0.05, abs=POS_TOL_M)
    assert (after["point"]["x"], after["point"]["y"]) == pytest.approx(
        (before["point"]["x"], before["point"]["y"]), abs=POS_TOL_M
    )
    assert out.strip() == f"tcp z: {before['point']['z']:.4f} -> {after['point']['z']:.4f} m"


@pytest.mark.sdk
def test_the_sdk_picks_comes_back_and_shows_the_controllers_refusal(url: str) -> None:
    out = run(url, sys.executable, "examples/sdk_pick.py").splitlines()
    assert out[0] == "picked at [90.0, -90.0, 90.0, -90.0, -90.0, 0.0]"
    assert out[1] == "back at [0.0, -90.0, 90.0, -90.0, -90.0, 0.0]"
    assert out[2] == 'refused: 412 "Unreachable Pose"'
    assert angles(url) == pytest.approx([0, -90, 90, -90, -90, 0], abs=ANGLE_TOL_DEG)


def test_the_example_program_runs_headless_and_sets_do1(url: str) -> None:
    out = run(url, "pendant", "run", "examples/pick_and_place.json", "--robot", url)
    assert "[loop 1/1] step 4/4: Gripper open (300 ms)" in out and "Finished: 1 loop(s)" in out
    assert angles(url) == pytest.approx([-40, -90, 90, -90, -90, 0], abs=ANGLE_TOL_DEG)
    assert httpx.get(f"{url}/signal/output/1", timeout=30.0).json() == "HIGH"
