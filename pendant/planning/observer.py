"""Following a run on the twin: the runner's clock and sleep, per-step durations, path samples and peak joint
speeds, and the inputs the program reads at the levels assumed (pendant.planning.preflight uses it)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from pendant.controller.types import MotionStatus, SignalLevel
from pendant.planning.budget import Budget
from pendant.planning.report import AssumedInput
from pendant.planning.twin import Twin, TwinSeed
from pendant.program.models import Step, WaitInputStep
from pendant.program.runner import RunProgress, RunState
from pendant.sim.planner import Plan
from pendant.sim.timeline import Motion

_MOVED_RAD = 1e-6
# Arm positions kept from a stretch of polls taken in one step (the clearance is computed at a few of them).
SAMPLES_PER_SKIP = 6
# Where the arm was when, for the page's playback: plenty for hours of program (then it stops growing).
MAX_TIMELINE = 20_000


class TooLong(Exception):
    """The run went past the simulated time it may take."""


@dataclass
class StepLog:
    duration_s: float = 0.0
    samples: list[np.ndarray] = field(default_factory=list)
    peak_speed: float = 0.0
    peak_joint: int | None = None


class CheckedTwin(Twin):
    """The twin as the runner sees it: inputs at their assumed levels; a wait sees the level it waits for.
    Every output, input read and motion poll checks the budget (a loop of outputs never sleeps)."""

    def __init__(
        self, seed: TwinSeed, model: str, given: Mapping[int, SignalLevel], budget: Budget | None = None
    ) -> None:
        self.budget = budget or Budget()
        super().__init__(seed, model)
        self.given = dict(given)
        self.waiting: WaitInputStep | None = None  # the wait step running now
        self.assumed: dict[int, AssumedInput] = {}
        for port, level in self.given.items():
            self.set_input(port, level)

    def set_output(self, port: int, level: SignalLevel) -> None:
        self.budget.check()
        super().set_output(port, level)

    def get_motion_status(self) -> MotionStatus:
        self.budget.check()
        return super().get_motion_status()

    def get_input(self, port: int) -> SignalLevel:
        self.budget.check()
        wait = self.waiting
        if wait is not None and wait.port == port and port not in self.given:
            self.assumed.setdefault(port, AssumedInput(wait.level, "the wait's level"))
            return wait.level
        level = super().get_input(port)
        self.assumed.setdefault(
            port, AssumedInput(level, "given" if port in self.given else "read from the arm")
        )
        return level


class RunObserver:
    """Follows the runner line by line on the twin's clock: durations, path samples, peak joint speeds."""

    def __init__(self, twin: CheckedTwin, listed: list[Step], deadline_s: float) -> None:
        self.twin = twin
        self.listed = listed
        self.logs: dict[int, StepLog] = {}
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
        self.logs.setdefault(line, StepLog())
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
        self.twin.budget.check()
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
            raise TooLong
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
