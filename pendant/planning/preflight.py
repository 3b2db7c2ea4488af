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
from dataclasses import dataclass, field

import numpy as np

from pendant.controller.types import SignalLevel
from pendant.planning.clearance import Clearance, Closest
from pendant.planning.refusal import explain
from pendant.planning.report import AssumedInput, FirstFailure, PreflightReport, StepCheck
from pendant.planning.twin import Twin, TwinSeed, TwinSetupError
from pendant.program.describe import describe_step
from pendant.program.models import CommentStep, LoopMode, LoopStep, Program, Step, WaitInputStep, children
from pendant.program.plan import Loader, PlanError
from pendant.program.runner import ProgramRunner, RunProgress, RunState
from pendant.program.tree import lines
from pendant.sim.planner import Plan
from pendant.sim.timeline import Motion

# Clearance is computed at this many points of each step's path at most (spread along it), so a long
# program stays inside its time budget; the planner itself checks every 2 degrees / 5 mm for collisions.
MAX_CLEARANCE_SAMPLES = 16
# A program that would run longer than this (simulated) is not checked to its end: a loop of a million
# passes is a program to shorten, not to wait for.
MAX_SIMULATED_S = 4 * 3600.0
MAX_LOOP_PASSES = 1000
_MOVED_RAD = 1e-6
# Arm positions kept from a stretch of polls taken in one step (the clearance is computed at a few of them).
SAMPLES_PER_SKIP = 6
# Where the arm was when, for the page's playback: plenty for hours of program (then it stops growing).
MAX_TIMELINE = 20_000


class PreflightRefused(Exception):
    """The program cannot be checked as it is (a missing or recursive Call, a twin that cannot be set up)."""


class _TooLong(Exception):
    pass


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


@dataclass
class _StepLog:
    duration_s: float = 0.0
    samples: list[np.ndarray] = field(default_factory=list)
    peak_speed: float = 0.0
    peak_joint: int | None = None


class _CheckedTwin(Twin):
    """The twin as the runner sees it: inputs at their assumed levels; a wait sees the level it waits for."""

    def __init__(self, seed: TwinSeed, model: str, given: Mapping[int, SignalLevel]) -> None:
        super().__init__(seed, model)
        self.given = dict(given)
        self.waiting: WaitInputStep | None = None  # the wait step running now
        self.assumed: dict[int, AssumedInput] = {}
        for port, level in self.given.items():
            self.set_input(port, level)

    def get_input(self, port: int) -> SignalLevel:
        wait = self.waiting
        if wait is not None and wait.port == port and port not in self.given:
            self.assumed.setdefault(port, AssumedInput(wait.level, "the wait's level"))
            return wait.level
        level = super().get_input(port)
        self.assumed.setdefault(
            port, AssumedInput(level, "given" if port in self.given else "read from the arm")
        )
        return level


class _Observer:
    """Follows the runner line by line on the twin's clock: durations, path samples, peak joint speeds."""

    def __init__(self, twin: _CheckedTwin, listed: list[Step], deadline_s: float) -> None:
        self.twin = twin
        self.listed = listed
        self.logs: dict[int, _StepLog] = {}
        self.line: int | None = None
        self.since = twin.now()
        self.started = twin.now()
        self.deadline = self.started + deadline_s
        self.last_q: np.ndarray | None = None
        self.seen_plans: set[int] = set()
        self.timeline: list[tuple[float, int, np.ndarray]] = []  # (s from the start, line, q): playback

    def on_progress(self, progress: RunProgress) -> None:
        if progress.state is RunState.RUNNING and progress.step_index is not None:
            self._enter(progress.step_index)

    def _enter(self, line: int) -> None:
        if line == self.line:
            return
        self._close()
        self.line = line
        step = self.listed[line] if line < len(self.listed) else None
        self.twin.waiting = step if isinstance(step, WaitInputStep) else None
        self.logs.setdefault(line, _StepLog())
        self._sample(force=True)

    def _close(self) -> None:
        now = self.twin.now()
        if self.line is not None:
            self.logs[self.line].duration_s += now - self.since
        self.since = now

    def finish(self) -> float:
        self._close()
        self.line = None
        return self.twin.now() - self.started

    def sleep(self, dt: float) -> None:
        """The runner's sleep: sample the arm, then move the twin's time on.

        While the arm is on its way to a single target nothing the runner reads changes, so the polls until
        it arrives are taken in one step, on the same grid: the runner sees what it would poll by poll."""
        self._sample()
        now = self.twin.now()
        polls = 1
        period = dt + self.twin.seed.poll_reads_s  # the sleep, then the poll's reads
        motion = self.twin.running_motion()
        # (a blended run is polled poll by poll: the runner tells which waypoint the arm heads for from where
        # it is, and so which step the time goes to)
        if motion is not None and dt > 0 and (motion.plan is None or len(motion.plan.waypoint_s) <= 1):
            boundary = min((t for t in _boundaries(motion) if t > now + period), default=now)
            polls = max(1, math.floor((boundary - now) / period))
            for k in np.linspace(0, polls - 1, min(polls, SAMPLES_PER_SKIP))[1:]:
                t = now + float(k) * period
                self._keep(motion.q_at(t), t)
        if now + polls * period > self.deadline:
            raise _TooLong
        self.twin.advance(polls * period)

    def _sample(self, force: bool = False) -> None:
        if self.line is None:
            return
        self._keep(self.twin.joint_positions(), self.twin.now(), force)
        motion = self.twin.running_motion()
        if motion is not None and motion.plan is not None and id(motion.plan) not in self.seen_plans:
            self.seen_plans.add(id(motion.plan))
            log = self.logs[self.line]
            speed, joint = _peak_speed(motion.plan)
            if speed > log.peak_speed:
                log.peak_speed, log.peak_joint = speed, joint

    def _keep(self, q: np.ndarray, t: float, force: bool = False) -> None:
        assert self.line is not None
        if force or self.last_q is None or float(np.max(np.abs(q - self.last_q))) > _MOVED_RAD:
            self.logs[self.line].samples.append(q)
            self.last_q = q
            if len(self.timeline) < MAX_TIMELINE:
                self.timeline.append((t - self.started, self.line, q))


def _boundaries(motion: Motion) -> list[float]:
    """When the running command passes its waypoints and ends (clock times)."""
    marks = (
        [] if motion.plan is None else [motion.t0 + motion.plan.time_at(s) for s in motion.plan.waypoint_s]
    )
    return [*marks, motion.t_end]


def _peak_speed(plan: Plan) -> tuple[float, int]:
    """The fastest joint speed (rad/s) along a planned motion, and which joint: |dq/ds| ds/dt at its grid."""
    scaling = plan.scaling
    speeds = np.array(
        [np.abs(plan.path.derivatives(s)[1]) * v for s, v in zip(scaling.s, scaling.v, strict=True)]
    )
    if speeds.size == 0:
        return 0.0, 0
    joint = int(np.argmax(np.max(speeds, axis=0)))
    return float(np.max(speeds[:, joint])), joint


def preflight(
    program: Program,
    seed: TwinSeed,
    *,
    model: str = "pulse75",
    load: Loader | None = None,
    inputs: Mapping[int, SignalLevel] | None = None,
    loop_passes: int = 1,
    max_simulated_s: float = MAX_SIMULATED_S,
) -> PreflightReport:
    """Check `program` on a twin of `seed`. Raises PreflightRefused when it cannot be checked at all."""
    if not 0 <= loop_passes <= MAX_LOOP_PASSES:
        raise PreflightRefused(f"while/until loop passes must be 0 to {MAX_LOOP_PASSES} (got {loop_passes})")
    began = time.perf_counter()
    try:
        twin = _CheckedTwin(seed, model, inputs or {})
    except TwinSetupError as error:
        raise PreflightRefused(str(error)) from error
    listed = [line.step for line in lines(program.steps)]
    observer = _Observer(twin, listed, max_simulated_s)

    def load_assuming(name: str) -> Program:
        assert load is not None
        return assume_loop_passes(load(name), loop_passes)

    runner = ProgramRunner(
        twin, sleep=observer.sleep, now=twin.now, load=None if load is None else load_assuming
    )
    runner.add_listener(observer.on_progress)
    notes = list(seed.notes)
    try:
        result = runner.run(assume_loop_passes(program, loop_passes))
    except PlanError as error:
        raise PreflightRefused(str(error)) from error
    except _TooLong:
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
