"""A pallet pick-and-place cell taught once, run three ways on a real `pendant --no-ui` (the simulator on the
real clock, over HTTP): `pendant run --robot URL`, the exported script, and `pendant run` on its own
simulator. The loop runs until DI1 is HIGH: the test sets it (PUT /sim/signal/input/1/high) when the cell
says a part was placed (DO1 HIGH, an action at the place waypoint)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from pendant.controller import MotionType, Pose, SignalLevel
from pendant.program import (
    GripperAction,
    GripperAtWaypoint,
    GripperStep,
    LoopMode,
    LoopStep,
    Offset,
    OutputAction,
    OutputStep,
    PalletStep,
    Program,
    ProgramStore,
    Waypoint,
    export_script,
)
from tests.support import preloaded
from tests.support.launchers import REPO_ROOT, running_pendant
from tests.support.programs import move, program_of
from tests.support.waiting import SAFETY_NET_S

pytestmark = pytest.mark.slow

RUN_TIMEOUT_S = 120.0
POLL_S = 0.02
POSITION_TOL_M = 0.002
SPEED = 100.0


@pytest.fixture(scope="module")
def api_url() -> Iterator[str]:
    with running_pendant() as url:
        yield url


def cell(waypoints: dict[str, Waypoint]) -> Program:
    """Pick from the next cell of a 2x2 tray (A, B, C its corners), place at C through a relative approach
    and retreat 50 mm above it, opening the gripper and saying "placed" (DO1) on arrival; until DI1."""
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    above_c = Offset(z=50.0)
    body = (
        PalletStep(
            name="tray",
            corners=("A", "B", "C"),
            rows=2,
            columns=2,
            approach_mm=40.0,
            speed=SPEED,
            body=(GripperStep(action=GripperAction.CLOSE, timeout_ms=100),),
        ),
        move(c, MotionType.JOINT, SPEED, offset=above_c).step,  # approach
        move(
            c,
            MotionType.LINEAR,
            SPEED,
            actions=(
                OutputAction(port=1, value=SignalLevel.HIGH),
                GripperAtWaypoint(value=GripperAction.OPEN),
            ),
        ).step,
        move(c, MotionType.LINEAR, SPEED, offset=above_c).step,  # retreat
        OutputStep(port=1, level=SignalLevel.LOW),
    )
    return program_of(
        move(a, speed=SPEED),
        LoopStep(mode=LoopMode.UNTIL, port=1, level=SignalLevel.HIGH, body=body),
        name="pallet cell",
        extra=(a, b, c),
    )


def pendant_run(*args: str) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(REPO_ROOT)}
    return preloaded.popen(
        [sys.executable, "-m", "pendant", "run", *args],
        cwd=REPO_ROOT,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )


def run_cell(api: httpx.Client, process: subprocess.Popen[str]) -> tuple[int, str, str]:
    """Wait for the first "placed" (DO1 HIGH), then say the tray is empty (DI1 HIGH); the process's end."""
    deadline = time.monotonic() + RUN_TIMEOUT_S
    while api.get("/signal/output/1").text.strip('"') != "HIGH":
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the cell never placed a part"
        time.sleep(POLL_S)
    api.put("/sim/signal/input/1/high").raise_for_status()
    out, err = process.communicate(timeout=RUN_TIMEOUT_S)
    return process.returncode, out, err


def retreat_point(waypoints: dict[str, Waypoint]) -> np.ndarray:
    p = waypoints["C"].position.point
    return np.array([p.x, p.y, p.z + 0.05])


def tcp(api: httpx.Client) -> np.ndarray:
    point = api.get("/position").json()["point"]
    return np.array([point["x"], point["y"], point["z"]])


@pytest.fixture
def api(api_url: str) -> Iterator[httpx.Client]:
    with httpx.Client(base_url=api_url, timeout=SAFETY_NET_S) as client:
        client.put("/sim/reset").raise_for_status()  # DI1 LOW, DO1 LOW, the arm at home
        yield client


def test_pendant_run_drives_the_cell_until_the_sensor_says_so(
    api: httpx.Client, api_url: str, waypoints: dict[str, Waypoint], tmp_path: Path
) -> None:
    ProgramStore(tmp_path).save(cell(waypoints), "pallet cell")
    code, out, err = run_cell(api, pendant_run(str(tmp_path / "pallet cell.json"), "--robot", api_url))
    assert code == 0, err
    assert "step 3/8: Pallet tray 2x2 from A, B, C (approach 40 mm)" in out  # progress per step
    assert out.rstrip().endswith("Finished: 1 loop(s)")
    np.testing.assert_allclose(tcp(api), retreat_point(waypoints), atol=POSITION_TOL_M)
    assert api.get("/signal/output/1").text.strip('"') == "LOW"


def test_the_exported_cell_does_the_same(
    api: httpx.Client, api_url: str, waypoints: dict[str, Waypoint], tmp_path: Path
) -> None:
    script = tmp_path / "cell.py"
    script.write_text(export_script(cell(waypoints)))
    process = subprocess.Popen(
        [sys.executable, str(script), api_url], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    code, _, err = run_cell(api, process)
    assert code == 0, err
    np.testing.assert_allclose(tcp(api), retreat_point(waypoints), atol=POSITION_TOL_M)
    assert api.get("/signal/output/1").text.strip('"') == "LOW"


def test_pendant_run_on_its_own_simulator_and_a_failure_names_step_and_message(
    waypoints: dict[str, Waypoint], tmp_path: Path
) -> None:
    a = waypoints["A"]
    store = ProgramStore(tmp_path)
    store.save(program_of(LoopStep(times=2, body=(move(a, speed=SPEED).step,)), extra=(a,)), "twice")
    done = pendant_run(str(tmp_path / "twice.json"), "--loops", "2").communicate(timeout=RUN_TIMEOUT_S)
    assert done[0].count("step 2/2: Move J to A @ 100%") == 2 and "Finished: 2 loop(s)" in done[0], done[1]

    far = Waypoint(name="Far", pose=Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0]), position=a.position)
    store.save(program_of(move(a, speed=SPEED), move(far, speed=SPEED)), "refused")
    process = pendant_run(str(tmp_path / "refused.json"))
    _, err = process.communicate(timeout=RUN_TIMEOUT_S)
    assert process.returncode == 1
    assert "Steps 1-2 (blended moves to A, Far) failed: Unreachable Pose" in err

    (tmp_path / "broken.json").write_text('{"schema_version": 9}')
    process = pendant_run(str(tmp_path / "broken.json"))
    _, err = process.communicate(timeout=RUN_TIMEOUT_S)
    assert process.returncode == 2 and "newer pendant" in err
