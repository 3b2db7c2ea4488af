"""Play a program on any Controller: blended moves, IO, waits; pause, step, stop; progress for the page.

Only the Controller protocol is used, so the same runner drives the simulator and a real arm. It learns that a
motion finished by polling the motion status (and the pose, to know which waypoint the arm is heading for).
Time comes from injected `now` and `sleep`, so tests run on the simulator's FakeClock without real sleeps.

Execution is a cursor over the program: `run`, `step` and `resume` move it forward in the calling thread
and return when the program ends, fails, is stopped or pauses. `start_*` run them on a worker thread.
"""

from __future__ import annotations

import logging
import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from enum import StrEnum

import numpy as np

from pendant.controller import Controller, ControllerError, MotionStatus
from pendant.controller.types import MotionType
from pendant.program.models import (
    GripperAction,
    GripperStep,
    MoveStep,
    OutputStep,
    Program,
    Step,
    WaitInputStep,
    WaitStep,
    describe_step,
)
from pendant.program.plan import MoveGroup, Segment, SingleStep, plan_segments

log = logging.getLogger(__name__)

POLL_S = 0.05
# A real controller may report IDLE for a moment after accepting a motion; past this, IDLE away from the
# target means the motion never started.
START_GRACE_S = 2.0
ARRIVAL_TOL_DEG = 0.5
ARRIVAL_TOL_M = 0.002
FAILED_STATES = {
    MotionStatus.MOTION_FAILED: "the motion failed (MOTION_FAILED)",
    MotionStatus.ERROR: "the controller is in ERROR",
    MotionStatus.EMERGENCY: "the arm is in EMERGENCY",
    MotionStatus.ZERO_GRAVITY: "the arm was relaxed (ZERO_GRAVITY)",
}


class RunState(StrEnum):
    IDLE = "idle"
    RUNNING = "running"
    PAUSED = "paused"
    FINISHED = "finished"
    STOPPED = "stopped"
    FAILED = "failed"


@dataclass(frozen=True)
class RunProgress:
    """What the page shows: the state, the step being executed (0-based), the loop, 0..1 and a sentence."""

    state: RunState = RunState.IDLE
    step_index: int | None = None
    loop: int = 1
    loops: int = 1  # 0: until stopped
    progress: float = 0.0
    message: str = "Ready"
    failed_step: int | None = None  # 0-based index of the step that failed

    @property
    def active(self) -> bool:
        """A run that can be resumed or stepped (running or paused)."""
        return self.state in (RunState.RUNNING, RunState.PAUSED)


class RunnerBusy(Exception):
    """A run is already executing on the worker thread."""


class _Interrupted(Exception):
    def __init__(self, resume_at: int) -> None:
        self.resume_at = resume_at


class _StepFailed(Exception):
    """Step `index` failed; `last` > index when a blended group was refused whole (any of its targets)."""

    def __init__(self, index: int, reason: str, last: int | None = None) -> None:
        self.index = index
        self.reason = reason
        self.last = last if last is not None else index


@dataclass
class _Cursor:
    program: Program
    loops: int
    loop: int = 1
    index: int = 0  # the next step to execute


Listener = Callable[[RunProgress], None]


class ProgramRunner:
    """Executes programs on `controller`; one run at a time. Thread-safe: pause/stop from any thread."""

    def __init__(
        self,
        controller: Controller,
        *,
        sleep: Callable[[float], None] = time.sleep,
        now: Callable[[], float] = time.monotonic,
        poll_s: float = POLL_S,
    ) -> None:
        self._controller = controller
        self._sleep = sleep
        self._now = now
        self._poll_s = poll_s
        self._lock = threading.RLock()
        self._cursor: _Cursor | None = None
        self._progress = RunProgress()
        self._pause_requested = False
        self._stop_requested = False
        self._listeners: list[Listener] = []
        self._worker: threading.Thread | None = None

    # --- observing ---------------------------------------------------------------------------------
    @property
    def progress(self) -> RunProgress:
        return self._progress

    def add_listener(self, listener: Listener) -> None:
        self._listeners.append(listener)

    def _publish(self, **changes: object) -> None:
        with self._lock:
            updated = replace(self._progress, **changes)  # type: ignore[arg-type]
            if updated == self._progress:
                return
            self._progress = updated
        for listener in list(self._listeners):
            try:
                listener(updated)
            except Exception:  # a broken view must not stop the arm's program
                log.exception("program progress listener failed")

    # --- commands (blocking: they return when the run ends or pauses) ------------------------------
    def run(self, program: Program, loops: int = 1) -> RunProgress:
        """Run `program` `loops` times (0: until stopped), blending consecutive moves."""
        self._begin(program, loops)
        return self._execute(single_step=False)

    def step(self, program: Program | None = None) -> RunProgress:
        """Execute one step, then pause. Continues a paused run; else starts `program` at its first step."""
        with self._lock:
            paused = self._cursor is not None and self._progress.state is RunState.PAUSED
        if not paused:
            if program is None:
                raise ValueError("nothing to step: no paused run and no program given")
            self._begin(program, 1)
        return self._execute(single_step=True)

    def resume(self) -> RunProgress:
        """Continue a paused run."""
        with self._lock:
            if self._cursor is None or self._progress.state is not RunState.PAUSED:
                return self._progress
        return self._execute(single_step=False)

    def pause(self) -> None:
        """Hold the arm where it is; `resume` continues from the waypoint it was heading for."""
        with self._lock:
            if self._progress.state is not RunState.RUNNING:
                return
            self._pause_requested = True
        self._freeze_quietly()

    def stop(self) -> None:
        """Freeze the arm now and end the run (a paused run too)."""
        with self._lock:
            running = self._progress.state is RunState.RUNNING
            self._stop_requested = running
        self._freeze_quietly()
        if not running:
            with self._lock:
                was_paused = self._progress.state is RunState.PAUSED
                self._cursor = None
            if was_paused:
                self._publish(state=RunState.STOPPED, message="Stopped")

    # --- worker thread -----------------------------------------------------------------------------
    @property
    def busy(self) -> bool:
        worker = self._worker
        return worker is not None and worker.is_alive()

    def start(self, command: Callable[[], RunProgress]) -> threading.Thread:
        """Run a blocking command (e.g. `lambda: runner.run(program, 3)`) on the worker thread."""
        with self._lock:
            if self.busy:
                raise RunnerBusy("A program is already running")
            worker = threading.Thread(target=command, name="pendant-program", daemon=True)
            self._worker = worker
        worker.start()
        return worker

    # --- execution ---------------------------------------------------------------------------------
    def _begin(self, program: Program, loops: int) -> None:
        if loops < 0:
            raise ValueError(f"loops must be >= 0 (got {loops})")
        with self._lock:
            if self._progress.state is RunState.RUNNING:
                raise RunnerBusy("A program is already running")
            self._cursor = _Cursor(program=program, loops=loops)
        self._publish(
            state=RunState.RUNNING,
            step_index=0,
            loop=1,
            loops=loops,
            progress=0.0,
            message="Starting",
            failed_step=None,
        )

    def _execute(self, *, single_step: bool) -> RunProgress:
        with self._lock:
            cursor = self._cursor
            if cursor is None:
                return self._progress
            self._pause_requested = False
            self._stop_requested = False
        self._publish(state=RunState.RUNNING, message=self._where(cursor))
        steps = cursor.program.steps
        try:
            while True:
                if cursor.index >= len(steps):
                    if cursor.loops == 0 or cursor.loop < cursor.loops:
                        cursor.loop += 1
                        cursor.index = 0
                        if not steps:
                            break
                        continue
                    break
                segment = plan_segments(steps[cursor.index :], blend=not single_step)[0]
                segment = _shifted(segment, cursor.index)
                self._publish(step_index=cursor.index, loop=cursor.loop, message=self._where(cursor))
                try:
                    self._run_segment(segment, cursor)
                except _Interrupted as interrupted:
                    cursor.index = interrupted.resume_at
                    return self._interrupted(cursor)
                cursor.index = segment.indices[-1] + 1
                self._publish(progress=self._fraction(cursor))
                if self._stop_requested or self._pause_requested:
                    return self._interrupted(cursor)
                if single_step:
                    if cursor.index >= len(steps):
                        if not (cursor.loops == 0 or cursor.loop < cursor.loops):
                            break
                        cursor.loop += 1
                        cursor.index = 0
                    return self._finish(
                        state=RunState.PAUSED,
                        step_index=cursor.index,
                        loop=cursor.loop,
                        message=f"Stepped: next is step {cursor.index + 1}",
                    )
        except _StepFailed as failure:
            # Stop the arm where it is: the rest of a blended group must not run on while the page says
            # "failed" (a controller error mid-run, a read that failed, a refused step).
            self._freeze_quietly()
            with self._lock:
                self._cursor = None
            step = steps[failure.index]
            if failure.last > failure.index:  # the controller refuses a blended run whole
                names = ", ".join(
                    s.waypoint.name
                    for s in steps[failure.index : failure.last + 1]
                    if isinstance(s, MoveStep)
                )
                what = f"Steps {failure.index + 1}-{failure.last + 1} (blended moves to {names})"
            else:
                what = f"Step {failure.index + 1} ({describe_step(step)})"
            return self._finish(
                state=RunState.FAILED,
                step_index=failure.index,
                failed_step=failure.index,
                message=f"{what} failed: {failure.reason}",
            )
        with self._lock:
            self._cursor = None
        return self._finish(state=RunState.FINISHED, progress=1.0, step_index=None, message="Finished")

    def _interrupted(self, cursor: _Cursor) -> RunProgress:
        if self._stop_requested:
            with self._lock:
                self._cursor = None
            return self._finish(state=RunState.STOPPED, message=f"Stopped at step {cursor.index + 1}")
        return self._finish(
            state=RunState.PAUSED,
            step_index=cursor.index,
            message=f"Paused before step {cursor.index + 1}",
        )

    def _finish(self, **changes: object) -> RunProgress:
        with self._lock:
            self._pause_requested = False
            self._stop_requested = False
        self._publish(**changes)
        return self._progress

    def _where(self, cursor: _Cursor) -> str:
        n = len(cursor.program.steps)
        loops = "∞" if cursor.loops == 0 else str(cursor.loops)
        return f"Running step {min(cursor.index + 1, n)}/{n}, loop {cursor.loop}/{loops}"

    def _fraction(self, cursor: _Cursor) -> float:
        n = max(len(cursor.program.steps), 1)
        if cursor.loops == 0:
            return cursor.index / n
        return ((cursor.loop - 1) * n + cursor.index) / (cursor.loops * n)

    # --- segments ----------------------------------------------------------------------------------
    def _run_segment(self, segment: Segment, cursor: _Cursor) -> None:
        if isinstance(segment, MoveGroup):
            self._run_moves(segment, cursor)
            return
        index, step = segment.index, segment.step
        try:
            self._run_single(index, step)
        except ControllerError as error:
            raise _StepFailed(index, error.message) from error

    def _check_interrupt(self, resume_at: int) -> None:
        if self._stop_requested or self._pause_requested:
            raise _Interrupted(resume_at)

    def _command(self, resume_at: int, send: Callable[[], object]) -> None:
        """Send a command unless interrupted; if an interrupt raced it, freeze again so it does not run."""
        self._check_interrupt(resume_at)
        send()
        if self._stop_requested or self._pause_requested:
            self._freeze_quietly()
            raise _Interrupted(resume_at)

    def _run_single(self, index: int, step: Step) -> None:
        controller = self._controller
        match step:
            case GripperStep():
                opening = step.action is GripperAction.OPEN
                gripper = controller.open_gripper if opening else controller.close_gripper
                started = self._now()
                self._command(index, lambda: gripper(step.timeout_ms))
                # The arm stays put while the gripper works: wait out the timeout and any queued motion.
                while True:
                    self._check_interrupt(index)
                    status = controller.get_motion_status()
                    self._raise_if_failed(index, status)
                    done_waiting = self._now() - started >= step.timeout_ms / 1000.0
                    if done_waiting and status is not MotionStatus.RUNNING:
                        return
                    self._sleep(self._poll_s)
            case OutputStep():
                self._command(index, lambda: controller.set_output(step.port, step.level))
            case WaitInputStep():
                started = self._now()
                while True:
                    self._check_interrupt(index)
                    if controller.get_input(step.port) is step.level:
                        return
                    if self._now() - started >= step.timeout_ms / 1000.0:
                        raise _StepFailed(
                            index, f"DI{step.port} did not go {step.level.value} within {step.timeout_ms} ms"
                        )
                    self._sleep(self._poll_s)
            case WaitStep():
                ends_at = self._now() + step.ms / 1000.0
                while (left := ends_at - self._now()) > 0:
                    self._check_interrupt(index)  # a paused wait starts over on resume
                    self._sleep(min(self._poll_s, left))
            case MoveStep():
                raise AssertionError("moves run as MoveGroup segments")

    def _run_moves(self, group: MoveGroup, cursor: _Cursor) -> None:
        controller = self._controller
        moves = group.moves
        joint = group.motion is MotionType.JOINT
        try:
            start = self._reading(joint)
            targets = [_target_of(move, joint) for move in moves]
            if joint:
                poses = [move.waypoint.pose for move in moves]
                self._command(group.first, lambda: controller.run_poses(poses, group.params))
            else:
                positions = [move.waypoint.position for move in moves]
                self._command(group.first, lambda: controller.run_positions(positions, group.params))
        except ControllerError as error:
            raise _StepFailed(group.first, error.message, last=group.indices[-1]) from error

        tol = ARRIVAL_TOL_DEG if joint else ARRIVAL_TOL_M
        issued_at = self._now()
        seen_running = False
        heading = 0
        while True:
            resume_at = group.first + heading
            self._check_interrupt(resume_at)
            try:
                status = controller.get_motion_status()
                here = self._reading(joint)
            except ControllerError as error:
                raise _StepFailed(resume_at, error.message) from error
            heading = max(heading, _heading(start, targets, here))
            if group.first + heading != self._progress.step_index:
                cursor.index = group.first + heading
                self._publish(step_index=cursor.index, message=self._where(cursor))
            self._raise_if_failed(group.first + heading, status)
            if status is MotionStatus.RUNNING:
                seen_running = True
            elif status is MotionStatus.IDLE:
                if _distance(here, targets[-1], joint) <= tol:
                    return
                if seen_running or self._now() - issued_at > START_GRACE_S:
                    raise _StepFailed(
                        group.first + heading,
                        f"the arm stopped before reaching {moves[heading].waypoint.name}",
                    )
            self._sleep(self._poll_s)

    def _reading(self, joint: bool) -> np.ndarray:
        """Where the arm is, in the space the group moves in: angles (degrees) or TCP point (metres)."""
        if joint:
            return np.asarray(self._controller.get_pose().angles, dtype=float)
        p = self._controller.get_position().point
        return np.array([p.x, p.y, p.z])

    def _raise_if_failed(self, index: int, status: MotionStatus) -> None:
        if status in FAILED_STATES:
            raise _StepFailed(index, FAILED_STATES[status])

    def _freeze_quietly(self) -> None:
        try:
            self._controller.freeze()
        except ControllerError as error:
            log.warning("freeze refused: %s", error.message)


def _shifted(segment: Segment, offset: int) -> Segment:
    if isinstance(segment, MoveGroup):
        return MoveGroup(segment.first + offset, segment.moves)
    return SingleStep(segment.index + offset, segment.step)


def _target_of(move: MoveStep, joint: bool) -> np.ndarray:
    if joint:
        return np.asarray(move.waypoint.pose.angles, dtype=float)
    p = move.waypoint.position.point
    return np.array([p.x, p.y, p.z])


def _distance(a: np.ndarray, b: np.ndarray, joint: bool) -> float:
    # Joints: the largest single-joint error (what a joint-space tolerance means); TCP: Euclidean metres.
    return float(np.max(np.abs(a - b))) if joint else float(np.linalg.norm(a - b))


def _heading(start: np.ndarray, targets: list[np.ndarray], here: np.ndarray) -> int:
    """Index of the target the arm is heading for: the leg of start -> t0 -> t1 ... nearest to `here`."""
    best, best_distance = 0, math.inf
    previous = start
    for index, target in enumerate(targets):
        leg = target - previous
        length2 = float(leg @ leg)
        t = 0.0 if length2 == 0.0 else float(np.clip((here - previous) @ leg / length2, 0.0, 1.0))
        distance = float(np.linalg.norm(previous + t * leg - here))
        if distance < best_distance - 1e-9:
            best, best_distance = index, distance
        previous = target
    return best
