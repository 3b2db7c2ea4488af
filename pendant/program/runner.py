"""Run control: play a program on any Controller with pause, step, stop, run-from and resume-after-failure,
publishing progress for the page (and for `pendant run`).

Only the Controller protocol is used, so the same runner drives the simulator and a real arm. The program is
compiled (pendant.program.plan), walked by the Interpreter and its leaves executed by a NodeExecutor
(pendant.program.motion). `run`, `step` and `resume` move forward in the calling thread and return when the
program ends, fails, is stopped or pauses; `start` runs them on a worker thread.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from enum import StrEnum

from pendant.controller import Controller, ControllerError
from pendant.program.describe import describe_step
from pendant.program.heard_stops import HeardStops
from pendant.program.interpreter import Interpreter, NodeFailed, Outcome
from pendant.program.models import Program
from pendant.program.motion import POLL_S, BlendedPath, Interrupted, NodeExecutor, PathPlanner, Timing
from pendant.program.plan import Loader, compile_program, line_count
from pendant.program.tree import lines

log = logging.getLogger(__name__)


class RunState(StrEnum):
    IDLE = "idle"
    RUNNING = "running"
    PAUSED = "paused"
    FINISHED = "finished"
    STOPPED = "stopped"
    FAILED = "failed"


@dataclass(frozen=True)
class RunProgress:
    """What the page shows: the state, the step line being executed (0-based), the loop, 0..1, a sentence."""

    state: RunState = RunState.IDLE
    step_index: int | None = None
    loop: int = 1
    loops: int = 1  # 0: until stopped
    progress: float = 0.0
    message: str = "Ready"
    failed_step: int | None = None  # 0-based line of the step that failed
    notice: str = ""  # how the controller plays what it cannot do as asked (e.g. paths stop-and-go)
    paused_because: str = ""  # a pause the operator did not ask for ("browser #1's page closed ...")

    @property
    def active(self) -> bool:
        """A run that can be resumed or stepped (running or paused)."""
        return self.state in (RunState.RUNNING, RunState.PAUSED)


# A run in these states keeps its place: Resume (paused), Retry or Skip (a failed step, a stop heard).
RESUMABLE = (RunState.PAUSED, RunState.FAILED, RunState.STOPPED)


FINISHING_S = 2.0  # how long a start waits for a run that has ended to finish telling its listeners


class RunnerBusy(Exception):
    """A run is already executing on the worker thread."""


Listener = Callable[[RunProgress], None]


@dataclass
class _Run:
    program: Program
    interpreter: Interpreter
    lines: int


class ProgramRunner:
    """Executes programs on `controller`; one run at a time. Thread-safe: pause/stop from any thread.

    `load` opens the programs that Call steps name; `blended` is a controller path that takes waypoint
    actions inside one blended request (else they are done stop-and-set); `planner` finds the paths of
    planned Move J steps (without one, such a step fails saying so)."""

    def __init__(
        self,
        controller: Controller,
        *,
        sleep: Callable[[float], object] = time.sleep,  # its result is ignored (FakeClock.advance)
        now: Callable[[], float] = time.monotonic,
        poll_s: float = POLL_S,
        load: Loader | None = None,
        blended: BlendedPath | None = None,
        planner: PathPlanner | None = None,
    ) -> None:
        self._controller = controller
        self.load = load
        self._blended = blended
        self._lock = threading.RLock()
        self._run: _Run | None = None
        self._progress = RunProgress()
        self._pause_requested = False
        self._stop_requested = False
        self._stop_cause = ""  # the page's Stop, said before it is heard on the stop bus (request_stop)
        self._paused_because = ""
        self._heard = HeardStops()  # stops from elsewhere (Freeze, the API): Retry stays possible
        self._listeners: list[Listener] = []
        self._worker: threading.Thread | None = None
        # A failed step's reason in the page's words (a bare "Collision detected" gets the obstacle named):
        # given the program, the failed lines (first, last: a blended group refused whole) and the reason.
        self.explain_failure: Callable[[Program, int, int, str], str] = lambda program, first, last, why: why
        # Collects a stop still on its way, before a failed step is judged and before every command is
        # sent (`pendant run` polls a pendant's stops: a stop the pendant heard since the last poll must
        # keep the next command from going out, and its protective stop may show as the step failing).
        self.hear_stops_now: Callable[[], None] = lambda: None
        self._executor = NodeExecutor(
            controller,
            Timing(sleep, now, poll_s),
            self._interrupt_requested,
            self._freeze_quietly,
            blended,
            notice=lambda text: self._publish(notice=text),
            planner=planner,
            before_send=lambda: self.hear_stops_now(),
        )

    # --- observing ---------------------------------------------------------------------------------
    @property
    def progress(self) -> RunProgress:
        return self._progress

    def add_listener(self, listener: Listener) -> None:
        self._listeners.append(listener)

    def _publish(self, **changes: object) -> None:
        with self._lock:
            updated = replace(self._progress, **changes)  # type: ignore[arg-type]  # RunProgress's own field names
            if updated == self._progress:
                return
            self._progress = updated
        for listener in list(self._listeners):
            try:
                listener(updated)
            except Exception:  # a broken view must not stop the arm's program
                log.exception("program progress listener failed")

    # --- commands (blocking: they return when the run ends or pauses) ------------------------------
    def run(self, program: Program, loops: int = 1, *, start_line: int = 0) -> RunProgress:
        """Run `program` `loops` times (0: until stopped), from line `start_line` (0: the first step)."""
        self._begin(program, loops, start_line)
        return self._execute(single_step=False, fresh=True)

    def step(self, program: Program | None = None) -> RunProgress:
        """Execute one step, then pause. Continues a paused run; else starts `program` at its first step."""
        with self._lock:
            paused = self._run is not None and self._progress.state is RunState.PAUSED
        if not paused:
            if program is None:
                raise ValueError("nothing to step: no paused run and no program given")
            self._begin(program, 1, 0)
        return self._execute(single_step=True, fresh=not paused)

    def resume(self) -> RunProgress:
        """Continue a paused run, or a failed or stopped one at the step it ended on (tried again)."""
        with self._lock:
            if self._run is None or self._progress.state not in RESUMABLE:
                return self._progress
        return self._execute(single_step=False)

    def skip(self) -> RunProgress:
        """Continue a failed or stopped run at the step after that one (that step is not done)."""
        with self._lock:
            if self._run is None or self._progress.state not in (RunState.FAILED, RunState.STOPPED):
                return self._progress
            self._run.interpreter.skip()
        return self._execute(single_step=False)

    @property
    def can_resume(self) -> bool:
        return self._run is not None and self._progress.state in RESUMABLE

    @property
    def resume_target(self) -> int | None:
        """Where a paused or failed run goes on: the waypoint, within the innermost step's moves (a Path
        step's recorded points), it heads for next; None with no run to resume."""
        run = self._run
        return run.interpreter.stack[-1].target if run is not None and run.interpreter.stack else None

    def pause(self, because: str = "") -> None:
        """Hold the arm where it is; `resume` continues from the waypoint it was heading for. `because`: a
        pause the operator did not ask for, said with the run's state until it runs again."""
        with self._lock:
            if self._progress.state is not RunState.RUNNING:
                return
            self._pause_requested = True
            self._paused_because = because
        self._freeze_quietly()

    def request_stop(self, cause: str = "") -> None:
        """The first half of `stop`, without the freeze (no controller call: safe on any thread): the run
        ends for good, "by `cause`", at its next look. The page's Stop says it before announcing itself on the
        stop bus, whose `stop_heard` alone would leave the run resumable: then whichever of the two the run
        hears first, it ends the same way."""
        with self._lock:
            self._stop_requested = self._progress.state is RunState.RUNNING
            self._stop_cause = cause or self._stop_cause

    def stop(self, cause: str = "") -> None:
        """Freeze the arm now and end the run for good (a paused, failed or stopped one too: it can no
        longer be resumed): the program's own Stop, the banner's Stop program. `cause` names who stopped
        it in the run's words; without one, a stop heard on the bus names it."""
        self.request_stop(cause)
        with self._lock:
            running = self._progress.state is RunState.RUNNING
        self._freeze_quietly()
        if not running:
            with self._lock:
                ended = self._run is not None and self._progress.state in RESUMABLE
                self._run = None
            if ended:
                message = self._progress.message
                message = message if message.startswith("Stopped") else "Stopped"
                self._publish(state=RunState.STOPPED, failed_step=None, message=message)

    def stop_heard(self, cause: str) -> None:
        """A stop from anywhere else (Freeze, Esc, another browser, `PUT /freeze`, a protective stop): the
        run ends at its next look, moving or not, as "Stopped at step N by <cause>", nothing after it is
        sent, and Retry or Skip stay possible as after a failure; a paused run becomes such a stopped run.
        Safe on any thread (a StopBus listener): it never talks to the controller, which the stop's own
        sender is freezing."""
        self._heard.hear(cause)
        with self._lock:  # a paused run that a Stop is ending for good is left to that Stop
            paused = self._progress.state is RunState.PAUSED and not self._stop_cause
            run = self._run if paused else None
        if run is not None:
            self._stopped_by(run)

    # --- worker thread -----------------------------------------------------------------------------
    @property
    def busy(self) -> bool:
        worker = self._worker
        return worker is not None and worker.is_alive()

    def join(self, timeout: float | None = None) -> bool:
        """Wait for the command started on the worker thread to end; whether it has (False: timed out)."""
        worker = self._worker
        if worker is not None:
            worker.join(timeout)
        return not self.busy

    def start(self, command: Callable[[], RunProgress]) -> threading.Thread:
        """Run a blocking command (e.g. `lambda: runner.run(program, 3)`) on the worker thread."""
        finishing = self._worker
        if (
            finishing is not None
            and finishing is not threading.current_thread()
            and self._progress.state is not RunState.RUNNING
        ):
            # A run that has just paused, stopped or failed still tells its listeners on its thread: a
            # Resume or Retry pressed as the banner appears waits for that instead of being refused.
            finishing.join(FINISHING_S)
        with self._lock:
            if self.busy:
                raise RunnerBusy("A program is already running")
            worker = threading.Thread(target=command, name="pendant-program", daemon=True)
            self._worker = worker
        worker.start()
        return worker

    # --- execution ---------------------------------------------------------------------------------
    def _begin(self, program: Program, loops: int, start_line: int) -> None:
        if loops < 0:
            raise ValueError(f"loops must be >= 0 (got {loops})")
        with self._lock:
            if self._progress.state is RunState.RUNNING:
                raise RunnerBusy("A program is already running")
            self._clear_requests()  # before the run shows as running: a stop from then on is heard
        plan = compile_program(program, self.load, actions_in_path=self._blended is not None)
        interpreter = Interpreter(plan, loops=loops)
        if start_line:
            interpreter.start_at(start_line)
        run = _Run(program, interpreter, line_count(program))
        interpreter.on_line = lambda line: self._publish(
            step_index=line, loop=interpreter.loop, progress=interpreter.fraction, message=self._where(run)
        )
        with self._lock:
            self._run = run
        self._publish(
            state=RunState.RUNNING,
            step_index=interpreter.line,
            loop=1,
            loops=loops,
            progress=0.0,
            message="Starting",
            failed_step=None,
        )

    def _execute(self, *, single_step: bool, fresh: bool = False) -> RunProgress:
        """Go on with the run; `fresh`: `_begin` has just cleared the requests (a stop since then counts)."""
        with self._lock:
            run = self._run
            if run is None:
                return self._progress
            if not fresh:
                self._clear_requests()
        interpreter = run.interpreter
        self._publish(state=RunState.RUNNING, failed_step=None, paused_because="", message=self._where(run))
        self._executor.begin()  # on the run's own thread: it reads the controller
        try:
            outcome = interpreter.run(self._executor, single_step=single_step)
        except Interrupted:
            return self._interrupted(run)
        except NodeFailed as failure:
            self.hear_stops_now()
            if self._stop_requested or self._heard.since_start:  # the stop landed between two looks
                return self._interrupted(run)
            if failure.stopped_by:  # the controller's own stop (not frozen: that would undo a relax)
                return self._stopped_by(run, failure.stopped_by)
            return self._failed(run, failure)
        except ControllerError as error:  # not expected (every read is a node's), but never left uncaught
            line = interpreter.line or 0
            return self._failed(run, NodeFailed(line, line, error.message))
        if outcome is Outcome.STEPPED and interpreter.line is not None:
            return self._finish(
                state=RunState.PAUSED,
                step_index=interpreter.line,
                loop=interpreter.loop,
                progress=interpreter.fraction,
                message=f"Stepped: next is step {interpreter.line + 1}",
            )
        with self._lock:
            self._run = None
        return self._finish(
            state=RunState.FINISHED, progress=1.0, step_index=None, loop=interpreter.loop, message="Finished"
        )

    def _failed(self, run: _Run, failure: NodeFailed) -> RunProgress:
        # Stop the arm where it is: the rest of a blended group must not run on while the page says "failed"
        # (a controller error mid-run, a read that failed, a refused step). Retry sends what is left.
        self._freeze_quietly()
        if failure.last_line > failure.line:  # the controller refuses a blended run whole
            what = f"Steps {failure.line + 1}-{failure.last_line + 1} (blended moves to {failure.targets})"
        else:
            listed = lines(run.program.steps)
            step = describe_step(listed[failure.line].step) if failure.line < len(listed) else "?"
            what = f"Step {failure.line + 1} ({step})"
        return self._finish(
            state=RunState.FAILED,
            step_index=failure.line,
            failed_step=failure.line,
            loop=run.interpreter.loop,
            message=f"{what} failed: {self._explained(run.program, failure)}",
        )

    def _explained(self, program: Program, failure: NodeFailed) -> str:
        try:
            return self.explain_failure(program, failure.line, failure.last_line, failure.reason)
        except Exception:  # words only: a broken explanation must not hide the failure itself
            log.exception("explaining a failed step failed")
            return failure.reason

    def _interrupted(self, run: _Run) -> RunProgress:
        # Frozen before the page hears of it: the Stop or Pause that asked freezes too, but on its own thread,
        # which may come after this one has said "Stopped" (a clean clone's run, beside a big file being read,
        # said so with the arm still moving: 0.05 deg more).
        self._freeze_quietly()
        line = run.interpreter.place
        if self._stop_requested:
            with self._lock:
                self._run = None
            said = self._stop_cause or (self._heard.cause if self._heard.since_start else "")
            cause = f" by {said}" if said else ""
            return self._finish(state=RunState.STOPPED, message=f"Stopped at step {line + 1}{cause}")
        if self._heard.since_start:
            # A stop heard late (`pendant run` polls its pendant's stops) may have come after the next command
            # went out: the freeze above keeps that command's motion from running on.
            return self._stopped_by(run)
        because = self._paused_because
        message = f"Paused before step {line + 1}" + (f": {because}" if because else "")
        return self._finish(state=RunState.PAUSED, step_index=line, message=message, paused_because=because)

    def _stopped_by(self, run: _Run, cause: str | None = None) -> RunProgress:
        """A stop heard elsewhere (or `cause`: the controller's own) ended the run: its place is kept for
        Retry or Skip, as a failed step's."""
        line = run.interpreter.place
        return self._finish(
            state=RunState.STOPPED,
            step_index=line,
            failed_step=line,
            loop=run.interpreter.loop,
            message=f"Stopped at step {line + 1} by {cause if cause is not None else self._heard.cause}",
        )

    def _clear_requests(self) -> None:
        self._paused_because = ""
        self._pause_requested = False
        self._stop_requested = False
        self._stop_cause = ""
        self._heard.start()

    def _finish(self, **changes: object) -> RunProgress:
        with self._lock:
            self._pause_requested = False
            self._stop_requested = False
        self._publish(**changes)
        return self._progress

    def _where(self, run: _Run) -> str:
        interpreter = run.interpreter
        line = interpreter.line
        loops = "∞" if interpreter.loops == 0 else str(interpreter.loops)
        return f"Running step {min((line or 0) + 1, run.lines)}/{run.lines}, loop {interpreter.loop}/{loops}"

    def _interrupt_requested(self) -> bool:
        return self._stop_requested or self._pause_requested or self._heard.since_start

    def _freeze_quietly(self) -> None:
        try:
            self._controller.freeze()
        except ControllerError as error:
            log.warning("freeze refused: %s", error.message)
