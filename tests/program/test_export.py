"""An exported script drives the simulator over real HTTP to the same end as the runner in-process."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from pendant.api import create_app
from pendant.controller import MotionType, Pose, SignalLevel
from pendant.controller.types import OUTPUT_PORTS
from pendant.program import (
    CallStep,
    CommentStep,
    GripperAction,
    GripperAtWaypoint,
    GripperStep,
    IfStep,
    LoopStep,
    Offset,
    OutputStep,
    Program,
    ProgramRunner,
    ProgramStore,
    RunState,
    WaitInputStep,
    WaitStep,
    Waypoint,
    export_script,
    program_operations,
)
from pendant.program.export import TOKEN_ENV
from pendant.sim import FakeClock, MonotonicClock, SimController
from tests.support.launchers import running_pendant
from tests.support.programs import move, program_of
from tests.support.threads import serve_in_thread

ANGLE_TOL_DEG = 1e-6
SCRIPT_TIMEOUT_S = 60.0
TOKEN = "test-access-token"


@pytest.fixture(scope="module")
def api_url() -> Iterator[str]:
    """One `pendant --no-ui` (simulator on real time) serving the API on a free loopback port."""
    with running_pendant() as url:
        yield url


def run_script(script: Path, *args: str, token_env: str | None = None) -> subprocess.CompletedProcess[str]:
    """Run an exported script with this Python; no access token inherited (`token_env` gives it one)."""
    env = {name: value for name, value in os.environ.items() if name != TOKEN_ENV}  # none inherited
    if token_env is not None:
        env[TOKEN_ENV] = token_env
    return subprocess.run(
        [sys.executable, str(script), *args],
        capture_output=True,
        text=True,
        timeout=SCRIPT_TIMEOUT_S,
        check=False,
        env=env,
    )


def pick_and_place(waypoints: dict[str, Waypoint]) -> Program:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    return program_of(
        move(a, speed=100.0),
        GripperStep(action=GripperAction.CLOSE, timeout_ms=100),
        OutputStep(port=1, level=SignalLevel.HIGH),
        move(b, motion=MotionType.LINEAR, speed=100.0),
        move(c, motion=MotionType.LINEAR, speed=100.0),
        WaitInputStep(port=1, level=SignalLevel.LOW, timeout_ms=500),
        GripperStep(action=GripperAction.OPEN, timeout_ms=100),
        OutputStep(port=2, level=SignalLevel.HIGH),
        WaitStep(ms=50),
        move(a, speed=100.0),
        move(b, speed=100.0),
        name="pick & place",
    )


def test_the_export_is_one_call_per_blended_group_and_valid_python(waypoints: dict[str, Waypoint]) -> None:
    program = pick_and_place(waypoints)
    operations = program_operations(program)
    assert [o["op"] for o in operations] == [
        "run_poses",
        "gripper",
        "output",
        "run_positions",
        "wait_input",
        "gripper",
        "output",
        "wait",
        "run_poses",
    ]
    assert operations[3]["steps"] == [4, 5] and operations[-1]["steps"] == [10, 11]
    source = export_script(program)
    ast.parse(source)
    assert "import httpx" in source and "pulse-api" in source  # says which client, and why


def test_the_exported_script_ends_where_the_runner_does(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint], tmp_path: Path, api_url: str
) -> None:
    program = pick_and_place(waypoints)
    in_process = ProgramRunner(sim, sleep=clock.advance, now=clock.now).run(program)
    assert in_process.state is RunState.FINISHED
    script = tmp_path / "pick_place.py"
    script.write_text(export_script(program))

    done = run_script(script, api_url)
    assert done.returncode == 0, done.stderr
    with httpx.Client(base_url=api_url, timeout=30.0) as api:
        pose = api.get("/pose").json()["angles"]
        outputs = {port: api.get(f"/signal/output/{port}").text.strip('"') for port in OUTPUT_PORTS}

    np.testing.assert_allclose(pose, sim.get_pose().angles, atol=ANGLE_TOL_DEG)
    assert outputs == {port: sim.get_output(port).value for port in OUTPUT_PORTS}
    assert outputs == {1: "HIGH", 2: "HIGH"}


def test_a_refused_step_exits_1_with_the_step_and_the_controller_message(
    tmp_path: Path, waypoints: dict[str, Waypoint], api_url: str
) -> None:
    a = waypoints["A"]
    far = a.model_copy(update={"name": "Far", "pose": Pose(angles=[0.0, -90.0, 400.0, -90.0, -90.0, 0.0])})
    program = program_of(
        WaitStep(ms=10),
        move(far, speed=100.0),
        OutputStep(port=1, level=SignalLevel.LOW),
    )
    script = tmp_path / "refused.py"
    script.write_text(export_script(program))
    done = run_script(script, api_url)
    assert done.returncode == 1
    assert (
        "Step 2 (Move J to Far @ 100%) failed: PUT /poses/run answered 412: Unreachable Pose" in done.stderr
    )


@pytest.fixture
def guarded_api() -> Iterator[tuple[SimController, str]]:
    """A simulator on real time behind an exposed pendant's API (token required), on a loopback port."""
    sim = SimController("pulse75", MonotonicClock())
    with serve_in_thread(create_app(sim, token=TOKEN)) as url:
        yield sim, url


def test_the_exported_script_sends_an_exposed_pendants_token(
    tmp_path: Path, waypoints: dict[str, Waypoint], guarded_api: tuple[SimController, str]
) -> None:
    sim, url = guarded_api
    a, b = waypoints["A"], waypoints["B"]
    program = program_of(
        move(a, speed=100.0),
        OutputStep(port=1, level=SignalLevel.HIGH),
        move(b, speed=100.0),
    )
    script = tmp_path / "guarded.py"
    script.write_text(export_script(program))
    start = sim.get_pose().angles

    without = run_script(script, url)
    assert without.returncode == 1
    assert "PUT /poses/run answered 401: This pendant is exposed on the network" in without.stderr
    assert "--token" in without.stderr  # says how to give it
    wrong = run_script(script, url, token_env="not-the-token")  # the variable is sent too
    assert wrong.returncode == 1
    assert "answered 403: Wrong access token" in wrong.stderr
    np.testing.assert_allclose(sim.get_pose().angles, start, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.LOW

    right = run_script(script, url, "--token", TOKEN)
    assert right.returncode == 0, right.stderr
    np.testing.assert_allclose(sim.get_pose().angles, b.pose.angles, atol=ANGLE_TOL_DEG)
    assert sim.get_output(1) is SignalLevel.HIGH


def test_every_step_type_exports_and_runs_like_the_runner(
    sim: SimController, clock: FakeClock, waypoints: dict[str, Waypoint], tmp_path: Path, api_url: str
) -> None:
    a, b, c = waypoints["A"], waypoints["B"], waypoints["C"]
    store = ProgramStore(tmp_path)
    store.save(program_of(move(c, speed=100.0), OutputStep(port=2, level=SignalLevel.HIGH)), "place")
    program = program_of(
        CommentStep(text="a comment runs nothing"),
        LoopStep(times=2, body=(move(a, speed=100.0).step, move(b, speed=100.0).step)),
        IfStep(  # DI4 is LOW on both: the else branch
            port=4,
            level=SignalLevel.HIGH,
            then=(OutputStep(port=1, level=SignalLevel.LOW),),
            otherwise=(OutputStep(port=1, level=SignalLevel.HIGH),),
        ),
        move(a, MotionType.LINEAR, 100.0, offset=Offset(z=30.0, rz=10.0), blend_mm=5.0),
        move(a, MotionType.LINEAR, 100.0, actions=(GripperAtWaypoint(value=GripperAction.CLOSE),)),
        CallStep(program="place"),  # C is in the called program's own table
        extra=(b,),
    )
    operations = program_operations(program, store.load)
    # The relative and the absolute LINEAR move blend into one call; the gripper closes once at the second.
    assert [o["op"] for o in operations] == ["loop", "if", "run_positions", "run_poses", "output"]
    targets = operations[2]["targets"]
    assert isinstance(targets, list) and len(targets) == 2
    assert operations[2]["actions"] == [{"target": "gripper", "value": "close"}]
    assert (
        operations[3]["steps"] == operations[4]["steps"] == [10]
    )  # the called program's steps: the Call's line
    in_process = ProgramRunner(sim, sleep=clock.advance, now=clock.now, load=store.load).run(program)
    assert in_process.state is RunState.FINISHED

    with httpx.Client(base_url=api_url, timeout=30.0) as api:
        api.put("/sim/reset").raise_for_status()
        script = tmp_path / "every_step.py"
        script.write_text(export_script(program, store.load))
        done = run_script(script, api_url)
        assert done.returncode == 0, done.stderr
        pose = api.get("/pose").json()["angles"]
        outputs = {port: api.get(f"/signal/output/{port}").text.strip('"') for port in OUTPUT_PORTS}
    np.testing.assert_allclose(pose, sim.get_pose().angles, atol=ANGLE_TOL_DEG)
    assert outputs == {port: sim.get_output(port).value for port in OUTPUT_PORTS} == {1: "HIGH", 2: "HIGH"}
