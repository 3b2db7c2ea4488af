"""An exported program plays a Path step as the runner does: one PUT /run/linear/positions with the corners'
blends, or, on a controller answering 404 to /run/*, one linear move per waypoint (and says so)."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import httpx
import numpy as np
import pytest

from pendant.api import create_app
from pendant.program import PathStep, Program, export_script, program_operations
from pendant.program.blended import FALLBACK_NOTE
from pendant.sim import FakeClock, MonotonicClock, SimController
from pendant.teach.path_step import path_step
from tests.support.path_playback import WithoutRunOperations, hand_drawn_s
from tests.support.threads import serve_in_thread

SCRIPT_TIMEOUT_S = 60.0
FAST_MM_S = 400.0  # the test's own path speed: the same run, sooner
END_TOL_M = 1e-6


@pytest.fixture(scope="module")
def program() -> Program:
    clock = FakeClock()
    step = path_step(hand_drawn_s(SimController(clock=clock), clock), name="s1")
    fast = PathStep.model_validate({**dict(step), "velocity_mm_s": FAST_MM_S})
    return Program(name="drawn", steps=(fast,))


@pytest.fixture
def served() -> Iterator[str]:
    with serve_in_thread(create_app(SimController(clock=MonotonicClock()))) as url:
        yield url


@pytest.fixture
def served_older() -> Iterator[str]:
    with serve_in_thread(WithoutRunOperations(create_app(SimController(clock=MonotonicClock())))) as url:
        yield url


def run_script(program: Program, url: str, tmp_path: Path) -> subprocess.CompletedProcess[str]:
    script = tmp_path / "drawn.py"
    script.write_text(export_script(program))
    return subprocess.run(
        [sys.executable, str(script), url],
        capture_output=True,
        text=True,
        timeout=SCRIPT_TIMEOUT_S,
        check=False,
    )


def end_of(program: Program) -> np.ndarray:
    step = program.steps[0]
    assert isinstance(step, PathStep)
    p = step.points[-1].position.point
    return np.array([p.x, p.y, p.z])


def tcp(url: str) -> np.ndarray:
    p = httpx.get(f"{url}/position", timeout=30.0).json()["point"]
    return np.array([p["x"], p["y"], p["z"]])


def test_the_export_is_an_approach_and_one_blended_run(program: Program) -> None:
    step = program.steps[0]
    assert isinstance(step, PathStep)
    approach, run = program_operations(program)
    assert approach["op"] == "run_poses" and approach["targets"] == [step.points[0].pose.angles]
    assert run["op"] == "run_path" and run["steps"] == [1] and run["velocity"] == FAST_MM_S / 1000.0
    targets = run["targets"]
    assert isinstance(targets, list) and len(targets) == len(step.points) - 1
    assert {t["blend"] for t in targets} == {step.blend_mm / 1000.0}


def test_the_exported_script_plays_the_path_in_one_run(program: Program, served: str, tmp_path: Path) -> None:
    done = run_script(program, served, tmp_path)
    assert done.returncode == 0, done.stderr
    assert FALLBACK_NOTE not in done.stderr
    np.testing.assert_allclose(tcp(served), end_of(program), atol=END_TOL_M)


def test_without_run_operations_the_script_plays_it_stop_and_go_and_says_so(
    program: Program, served_older: str, tmp_path: Path
) -> None:
    done = run_script(program, served_older, tmp_path)
    assert done.returncode == 0, done.stderr
    assert FALLBACK_NOTE in done.stderr
    np.testing.assert_allclose(tcp(served_older), end_of(program), atol=END_TOL_M)
