"""Pre-flight: run the program as it is now on the twin, with the same plan and runner as a real run, and
report per step what the arm would do (pendant.planning.report).

The runner's `sleep` advances the twin's clock instead of waiting, so a minute of program is checked in a
fraction of a second; each tick also samples where the arm is, for the clearance to the cell and the peak
joint speed of the step running. Inputs the program reads are assumed (given, or as the arm reads them now;
a Wait-for-input is assumed to see the level it waits for unless that input was given); a while/until
loop runs the number of passes assumed (default 1). Nothing is sent to the arm: the twin is a copy.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping

import numpy as np

from pendant.controller.types import SignalLevel
from pendant.planning.budget import Budget, OverBudget
from pendant.planning.clearance import Clearance, Closest
from pendant.planning.live import ControllerPlanner
from pendant.planning.observer import CheckedTwin, RunObserver, TooLong
from pendant.planning.refusal import explain
from pendant.planning.report import FirstFailure, PreflightReport, StepCheck
from pendant.planning.twin import TwinSeed, TwinSetupError
from pendant.program.describe import describe_step
from pendant.program.models import CommentStep, LoopMode, LoopStep, Program, Step, children
from pendant.program.plan import Loader, PlanError, compile_program
from pendant.program.runner import ProgramRunner, RunState
from pendant.program.tree import lines

# Clearance is computed at this many points of each step's path at most (spread along it), so a long
# program stays inside its time budget; the planner itself checks every 2 degrees / 5 mm for collisions.
MAX_CLEARANCE_SAMPLES = 16
# A program that would run longer than this (simulated) is not checked to its end: a loop of a million
# passes is a program to shorten, not to wait for.
MAX_SIMULATED_S = 4 * 3600.0
MAX_LOOP_PASSES = 1000


class PreflightRefused(Exception):
    """The program cannot be checked as it is (a missing or recursive Call, a twin that cannot be set up)."""


class PreflightOverBudget(PreflightRefused):
    """The program would take more steps or time to check than a pre-flight may (pendant.planning.budget)."""


def assume_loop_passes(program: Program, passes: int) -> Program:
    """The program with every while/until loop made a loop of `passes` passes (lines unchanged)."""

    def convert(steps: tuple[Step, ...]) -> tuple[Step, ...]:
        converted: list[Step] = []
        for step in steps:
            update: dict[str, object] = {name: convert(inner) for name, inner in children(step)}
            if isinstance(step, LoopStep) and step.mode is not LoopMode.TIMES:
                update |= {"mode": LoopMode.TIMES, "times": passes}
            converted.append(step.model_copy(update=update) if update else step)
        return tuple(converted)

    return program.model_copy(update={"steps": convert(program.steps)})


def preflight(
    program: Program,
    seed: TwinSeed,
    *,
    model: str = "pulse75",
    load: Loader | None = None,
    inputs: Mapping[int, SignalLevel] | None = None,
    loop_passes: int = 1,
    max_simulated_s: float = MAX_SIMULATED_S,
    budget: Budget | None = None,
) -> PreflightReport:
    """Check `program` on a twin of `seed`. Raises PreflightRefused when it cannot be checked at all,
    PreflightOverBudget when it would take more steps or time than `budget` (default: Budget())."""
    if not 0 <= loop_passes <= MAX_LOOP_PASSES:
        raise PreflightRefused(f"while/until loop passes must be 0 to {MAX_LOOP_PASSES} (got {loop_passes})")
    began = time.perf_counter()
    budget = budget or Budget()

    def load_assuming(name: str) -> Program:
        assert load is not None
        return assume_loop_passes(load(name), loop_passes)

    assumed = assume_loop_passes(program, loop_passes)
    try:
        budget.check_steps(compile_program(assumed, None if load is None else load_assuming))
        twin = CheckedTwin(seed, model, inputs or {}, budget)
    except PlanError as error:
        raise PreflightRefused(str(error)) from error
    except OverBudget as error:
        raise PreflightOverBudget(str(error)) from error
    except TwinSetupError as error:
        raise PreflightRefused(str(error)) from error
    listed = [line.step for line in lines(program.steps)]
    observer = RunObserver(twin, listed, max_simulated_s)

    runner = ProgramRunner(
        twin,
        sleep=observer.sleep,
        now=twin.now,
        load=None if load is None else load_assuming,
        planner=ControllerPlanner(twin.arm),  # a planned Move J plans on the twin, in the cell as seeded
    )
    runner.add_listener(observer.on_progress)
    notes = list(seed.notes)
    try:
        result = runner.run(assumed)
    except PlanError as error:
        raise PreflightRefused(str(error)) from error
    except OverBudget as error:
        raise PreflightOverBudget(str(error)) from error
    except TooLong:
        result = None
        notes.append(f"checked only the first {max_simulated_s / 3600:g} h of the program: it runs longer")
    cycle_time = observer.finish()
    clearance = Clearance(twin.arm, list(seed.obstacles), seed.tool_shape, seed.tool)
    failure: FirstFailure | None = None
    failed_line: int | None = None
    failure_reason = failure_obstacle = None
    if result is not None and result.state is RunState.FAILED and result.failed_step is not None:
        failed_line = result.failed_step
        message = result.message.split(" failed: ", 1)[-1]
        explained = explain(twin.last_refusal, message, twin.arm, clearance)
        failure_reason, failure_obstacle = explained.reason, explained.obstacle
        failure = FirstFailure(
            failed_line + 1, describe_step(listed[failed_line]), failure_reason, failure_obstacle
        )
    checks = []
    refusal = twin.last_refusal
    for index, step in enumerate(listed):
        log = observer.logs.get(index)
        failed = index == failed_line
        samples = [] if log is None else list(log.samples)
        if failed and refusal is not None and refusal.q is not None:
            samples.append(refusal.q)  # where it would collide: the step's closest approach
        closest = _closest(clearance, samples)
        if log is None:
            note = (
                "a comment"
                if isinstance(step, CommentStep)
                else f"not checked: step {failed_line + 1} failed first"
                if failed_line is not None and index > failed_line
                else "not run with the inputs assumed"
            )
        else:
            note = None
        ok = not failed and not (log is None and failed_line is not None and index > failed_line)
        checks.append(
            StepCheck(
                line=index + 1,
                step=describe_step(step),
                ok=ok,
                checked=log is not None,
                reason=failure_reason if failed else None,
                note=note,
                obstacle=failure_obstacle if failed else None,
                duration_s=0.0 if log is None else log.duration_s,
                min_clearance_mm=None if closest is None else closest.mm,
                closest_link=None if closest is None else closest.link,
                closest_obstacle=None if closest is None else closest.obstacle,
                peak_joint_speed_deg_s=None if log is None else math.degrees(log.peak_speed),
                peak_joint=None if log is None or log.peak_joint is None else log.peak_joint + 1,
            )
        )
    return PreflightReport(
        program=program.name,
        steps=tuple(checks),
        cycle_time_s=cycle_time,
        assumed_inputs=dict(twin.assumed),
        loop_passes=loop_passes,
        first_failure=failure,
        notes=tuple(notes),
        elapsed_s=time.perf_counter() - began,
        timeline=tuple(observer.timeline),
        failure_q=None if failed_line is None or refusal is None else refusal.q,
    )


def _closest(clearance: Clearance, samples: list[np.ndarray]) -> Closest | None:
    if clearance.empty or not samples:
        return None
    count = len(samples)
    picks = sorted(
        {round(k * (count - 1) / max(MAX_CLEARANCE_SAMPLES - 1, 1)) for k in range(MAX_CLEARANCE_SAMPLES)}
    )
    found = [c for c in (clearance(samples[min(k, count - 1)]) for k in picks) if c is not None]
    return min(found, key=lambda c: c.mm, default=None)
