"""A pre-flight's budget (issue #32): the steps a program would run are counted before anything runs, the
wall time is checked while it runs, and quitting stops it; past any of them it is refused with the reason.
On a real twin of the embedded simulator, and through `pendant preflight`."""

from __future__ import annotations

import json
import threading
from pathlib import Path

import pytest

from pendant.planning.budget import MAX_STEPS_RUN, Budget
from pendant.planning.command import EXIT_REFUSED
from pendant.planning.command import main as preflight_main
from pendant.planning.preflight import PreflightOverBudget, preflight
from pendant.planning.twin import TwinSeed, read_seed
from pendant.program.models import IfStep, LoopStep, MoveStep, OutputStep, Program
from pendant.sim import SimController
from tests.support.preflight_scene import LEFT_DEG, RIGHT_DEG, waypoint

DO1 = OutputStep(port=1, level="HIGH")  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def seed() -> TwinSeed:
    return read_seed(SimController())


def outputs(passes: int, per_pass: int) -> Program:
    """Loop `passes` x (`per_pass` outputs): 1 + passes * per_pass steps run."""
    return Program(name="outputs", steps=(LoopStep(times=passes, body=(DO1,) * per_pass),))


def swings(passes: int) -> Program:
    """Loop `passes` x (Move J left, Move J right): seconds of checking per hundred passes."""
    moves = (MoveStep(waypoint="left", speed=100.0), MoveStep(waypoint="right", speed=100.0))
    return Program(
        name="swings",
        waypoints=(waypoint("left", LEFT_DEG), waypoint("right", RIGHT_DEG)),
        steps=(LoopStep(times=passes, body=moves),),
    )


def test_a_program_within_the_step_budget_is_checked_and_one_step_more_is_refused(seed: TwinSeed) -> None:
    report = preflight(outputs(333, 3), seed, budget=Budget(max_steps=1000))  # 1 + 999 steps
    assert report.ok

    with pytest.raises(PreflightOverBudget, match=r"would run 1,003 steps .* at most 1,000"):
        preflight(outputs(334, 3), seed, budget=Budget(max_steps=1000))


def test_a_branch_counts_its_longer_side_and_nested_loops_multiply(seed: TwinSeed) -> None:
    branch = IfStep(port=1, level="HIGH", then=(DO1,) * 5, otherwise=(DO1,))  # type: ignore[arg-type]
    inner = LoopStep(times=1_000_000, body=(branch,))
    program = Program(name="nested", steps=(LoopStep(times=1_000_000, body=(inner,)),))
    # 1 + 1e6 * (1 + 1e6 * (1 + 5)) steps: refused before the twin is even set up
    with pytest.raises(PreflightOverBudget, match="6,000,001,000,001 steps"):
        preflight(program, seed)


def test_a_pre_flight_past_its_wall_time_is_stopped_with_the_reason(seed: TwinSeed) -> None:
    program = swings(5000)  # 10,001 steps: within the step budget, minutes of checking
    assert MAX_STEPS_RUN > 10_001
    with pytest.raises(PreflightOverBudget, match="longer than 1 s"):
        preflight(program, seed, budget=Budget(max_wall_s=1.0))


def test_cancelling_stops_a_running_pre_flight(seed: TwinSeed) -> None:
    budget = Budget()
    threading.Timer(0.5, budget.cancel.set).start()
    with pytest.raises(PreflightOverBudget, match="quitting"):
        preflight(swings(5000), seed, budget=budget)


def test_the_command_refuses_a_program_over_budget_with_the_reason(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "spin.json"
    spin = Program(
        name="spin", steps=(LoopStep(times=1_000_000, body=(LoopStep(times=1_000_000, body=(DO1,)),)),)
    )
    path.write_text(json.dumps(spin.model_dump(mode="json")))
    assert preflight_main([str(path)]) == EXIT_REFUSED
    assert "a pre-flight checks at most 100,000" in capsys.readouterr().err
