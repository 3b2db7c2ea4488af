"""Scripted events: make something happen to the simulator at an exact moment of its simulated time.

Three kinds of moment: a simulated time, the instant a run reaches its k-th waypoint, and the N-th command
sent to the API. A timed event puts a stop on the clock (`ScaledClock.add_stop`): simulated time cannot pass
it until the event has happened, so every reader sees the simulator either before the event or after it, at
exactly its time, however late the event's thread wakes up. Between events nothing runs.

`ScriptedSim` is the simulator with the hooks the waypoint events need: it remembers each queued run's
waypoints, holding the clock during the command, so a run cannot start moving before its waypoint times are
known.
"""

from __future__ import annotations

import heapq
import itertools
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from pendant.controller.errors import ControllerError
from pendant.controller.types import MotionParams, Pose, Position
from pendant.kinematics.transforms import inverse, position_to_matrix
from pendant.sim.clock import ScaledClock, paused
from pendant.sim.controller import SimController
from pendant.sim.timeline import Motion

Action = Callable[[], object]
T = TypeVar("T")

# A waypoint counts as reached at the arm's nearest approach to it, found on this many samples of the run
# (at least one per 10 ms of simulated time), then refined to REFINE_S; blended runs pass within 1 mm / 0.5°.
MIN_SAMPLES = 200
MAX_SAMPLES = 6000
SAMPLE_STEP_S = 0.01
REFINE_S = 1e-4
# How near a sample must come to count as the pass by a waypoint (a blend's worst case, with margin).
NEAR_RAD = np.radians(2.0)
NEAR_M = 0.005


@dataclass
class ScriptedEvent:
    """One scripted event; `fired_at` is the simulated time it happened (None: not yet)."""

    description: str
    action: Action
    fired_at: float | None = None
    error: BaseException | None = field(default=None, repr=False)


@dataclass(frozen=True)
class _Run:
    """What a queued motion was asked to pass: joint targets (rad) or TCP points (m, zero-point frame)."""

    targets: list[np.ndarray]
    joint_space: bool
    T_zero_origbase: np.ndarray
    T_flange_tool: np.ndarray


class Script:
    """The scripted events of one simulator; a daemon thread fires the timed ones."""

    def __init__(self, sim: SimController, clock: ScaledClock) -> None:
        self._sim = sim
        self._clock = clock
        self._cond = threading.Condition()
        self._timed: list[tuple[float, int, ScriptedEvent]] = []
        self._seq = itertools.count()
        self._on_command: dict[int, list[ScriptedEvent]] = {}
        self._waypoint_waiting: list[tuple[int, ScriptedEvent]] = []
        self._runs: dict[int, _Run] = {}  # id(Motion) -> its waypoints, for the motions still queued
        self.commands = 0
        self.origin = clock.now()  # "at simulated time t" counts from here (reset moves it)
        self.errors: list[tuple[ScriptedEvent, BaseException]] = []
        self._closed = False
        self._thread = threading.Thread(target=self._fire_timed, name="pendant-sim-script", daemon=True)
        self._thread.start()

    # --- arming ---------------------------------------------------------------------------------------------

    def at(self, t: float, action: Action, description: str) -> ScriptedEvent:
        """`action` at simulated time `t` after the origin (exactly: the clock waits for it)."""
        if not t >= 0:
            raise ValueError(f"a scripted time must be >= 0 s (got {t})")
        event = ScriptedEvent(description, action)
        try:
            self._at_absolute(self.origin + float(t), event)
        except ValueError:
            passed = self._clock.now() - self.origin
            raise ValueError(f"{description}: the test's simulated time is already {passed:g} s") from None
        return event

    def _at_absolute(self, t_abs: float, event: ScriptedEvent) -> None:
        with self._cond:
            self._clock.add_stop(t_abs)
            heapq.heappush(self._timed, (t_abs, next(self._seq), event))
            self._cond.notify()

    def on_command(self, n: int, action: Action, description: str) -> ScriptedEvent:
        """`action` when the n-th command (PUT/POST/DELETE to the PULSE API) arrives, before it is handled."""
        if n < 1:
            raise ValueError(f"commands are counted from 1 (got {n})")
        event = ScriptedEvent(description, action)
        with self._cond:
            self._on_command.setdefault(int(n), []).append(event)
        return event

    def on_waypoint(self, k: int, action: Action, description: str) -> ScriptedEvent:
        """`action` when the run now moving (else the next one queued) reaches its k-th waypoint (from 1)."""
        if k < 1:
            raise ValueError(f"waypoints are counted from 1 (got {k})")
        event = ScriptedEvent(description, action)
        held = self._clock.hold()  # the run now moving must not pass waypoint k while its time is found
        try:
            with self._cond:
                running = [m for m in self._sim.queued_motions() if id(m) in self._runs]
                if running:
                    self._bind(running[0], self._runs[id(running[0])], k, event)
                else:
                    self._waypoint_waiting.append((int(k), event))
        finally:
            self._clock.remove_stop(held)
        return event

    # --- hooks ----------------------------------------------------------------------------------------------

    def command_received(self) -> list[ScriptedEvent]:
        """Count a command; the events due on it (the caller runs them with `fire`)."""
        with self._cond:
            self.commands += 1
            return self._on_command.pop(self.commands, [])

    def run_queued(self, motion: Motion, run: _Run) -> None:
        """A run was queued (the clock is held, so it has not moved yet): bind the waiting waypoint events."""
        with self._cond:
            queued = {id(m) for m in self._sim.queued_motions()}
            self._runs = {key: value for key, value in self._runs.items() if key in queued}
            self._runs[id(motion)] = run
            waiting, self._waypoint_waiting = self._waypoint_waiting, []
            for k, event in waiting:
                self._bind(motion, run, k, event)

    def _bind(self, motion: Motion, run: _Run, k: int, event: ScriptedEvent) -> None:
        if k > len(run.targets):
            count = len(run.targets)
            plural = "" if count == 1 else "s"
            self.errors.append((event, ValueError(f"the run has only {count} waypoint{plural}")))
            return
        try:
            self._at_absolute(waypoint_times(motion, run, self._sim)[k - 1], event)
        except ValueError:
            self.errors.append((event, ValueError(f"waypoint {k} was already passed")))

    # --- firing ---------------------------------------------------------------------------------------------

    def fire(self, event: ScriptedEvent) -> None:
        """Run one event now; an action that raises is kept in `errors` (the test reports it)."""
        event.fired_at = self._clock.now() - self.origin
        try:
            event.action()
        except Exception as error:
            event.error = error
            self.errors.append((event, error))

    def _fire_timed(self) -> None:
        while True:
            with self._cond:
                if self._closed:
                    return
                if not self._timed:
                    self._cond.wait()
                    continue
                t_abs, _, event = self._timed[0]
                wait = self._clock.wall_seconds_until(t_abs)
                if wait > 0 or self._clock.now() < t_abs:
                    # Not yet; or an earlier stop still holds the clock (a command being queued).
                    self._cond.wait(max(wait, 0.0005))
                    continue
                heapq.heappop(self._timed)
            self.fire(event)  # the clock reads t_abs throughout: the event happens at that instant
            self._clock.remove_stop(t_abs)

    def reset(self) -> None:
        """Forget every event and count (a new test); simulated time counts from here."""
        with self._cond:
            self._timed.clear()
            self._on_command.clear()
            self._waypoint_waiting.clear()
            self._runs.clear()
            self._clock.clear_stops()
            self.commands = 0
            self.errors = []
            self.origin = self._clock.now()
            self._cond.notify()

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._cond.notify()
        self._thread.join(timeout=5.0)
        self._clock.clear_stops()


def waypoint_times(motion: Motion, run: _Run, sim: SimController) -> list[float]:
    """The simulated time at which `motion` reaches each of its waypoints (nearest approach, in order);
    the last one is where it stops."""
    t0, t_end = motion.t0, motion.t_end
    if len(run.targets) == 1 or motion.duration <= 0.0:
        return [t_end] * len(run.targets)
    count = int(min(MAX_SAMPLES, max(MIN_SAMPLES, motion.duration / SAMPLE_STEP_S)))
    times = np.linspace(t0, t_end, count)
    step = times[1] - times[0]
    samples = np.array([_coordinates(motion.q_at(float(t)), run, sim) for t in times])
    near = NEAR_RAD if run.joint_space else NEAR_M
    result: list[float] = []
    start = 0
    for target in run.targets[:-1]:
        distance = _distances(samples, target, run.joint_space)
        # The first pass within reach after the previous waypoint: the sample nearest it on that pass.
        close = np.flatnonzero(distance[start:] <= near)
        i = start + int(close[0]) if len(close) else start + int(np.argmin(distance[start:]))
        while i + 1 < count and distance[i + 1] <= distance[i]:
            i += 1
        t = _refine(motion, run, sim, target, float(times[i]) - step, float(times[i]) + step)
        result.append(min(max(t, t0), t_end))
        start = i
    result.append(t_end)
    return result


def _coordinates(q: np.ndarray, run: _Run, sim: SimController) -> np.ndarray:
    if run.joint_space:
        return np.asarray(q, dtype=float)
    return (run.T_zero_origbase @ sim.arm.fk(q) @ run.T_flange_tool)[:3, 3]


def _distances(samples: np.ndarray, target: np.ndarray, joint_space: bool) -> np.ndarray:
    diff = samples - target
    return np.max(np.abs(diff), axis=-1) if joint_space else np.linalg.norm(diff, axis=-1)


def _refine(motion: Motion, run: _Run, sim: SimController, target: np.ndarray, lo: float, hi: float) -> float:
    """Golden-section search for the nearest approach in [lo, hi]."""
    ratio = (np.sqrt(5.0) - 1.0) / 2.0

    def distance(t: float) -> float:
        return float(_distances(_coordinates(motion.q_at(t), run, sim), target, run.joint_space))

    a, b = lo, hi
    while b - a > REFINE_S:
        c, d = b - ratio * (b - a), a + ratio * (b - a)
        if distance(c) <= distance(d):
            b = d
        else:
            a = c
    return 0.5 * (a + b)


class ScriptedSim(SimController):
    """The simulator, telling its `Script` about each run it queues (for the waypoint events)."""

    script: Script

    def attach(self, script: Script) -> None:
        self.script = script

    def set_pose(self, pose: Pose, params: MotionParams) -> None:
        self._watched(lambda: SimController.set_pose(self, pose, params), [pose], joint_space=True)

    def run_poses(self, poses: list[Pose], params: MotionParams) -> None:
        self._watched(lambda: SimController.run_poses(self, poses, params), poses, joint_space=True)

    def set_position(self, position: Position, params: MotionParams) -> Position:
        return self._watched(
            lambda: SimController.set_position(self, position, params), [position], joint_space=False
        )

    def run_positions(self, positions: list[Position], params: MotionParams) -> None:
        self._watched(
            lambda: SimController.run_positions(self, positions, params), positions, joint_space=False
        )

    def _watched(
        self, command: Callable[[], T], waypoints: Sequence[Pose | Position], joint_space: bool
    ) -> T:
        script = getattr(self, "script", None)
        if script is None:
            return command()
        # Simulated time stands still until the run's waypoint times are known (over HTTP the command's
        # handling holds it already; this covers direct calls).
        with paused(self.clock):
            before = {id(m) for m in self.queued_motions()}
            result = command()
            new = [m for m in self.queued_motions() if id(m) not in before and m.plan is not None]
            if new:
                try:
                    run = self._run_of(waypoints, joint_space)
                except ControllerError:  # a fault came in meanwhile: the run is gone with the queue
                    return result
                script.run_queued(new[0], run)
            return result

    def _run_of(self, waypoints: Sequence[Pose | Position], joint_space: bool) -> _Run:
        if joint_space:
            targets = [np.radians(w.angles) for w in waypoints if isinstance(w, Pose)]
        else:
            targets = [
                np.array([w.point.x, w.point.y, w.point.z]) for w in waypoints if isinstance(w, Position)
            ]
        return _Run(
            targets=targets,
            joint_space=joint_space,
            T_zero_origbase=inverse(position_to_matrix(self.get_base())),
            T_flange_tool=position_to_matrix(self.get_tool().position),
        )
