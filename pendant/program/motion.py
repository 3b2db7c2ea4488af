"""Executing one plan node on a Controller: a blended move (then its waypoint actions), a gripper, output or
wait step, and reading an input for a Loop or If.

It learns that a motion finished by polling the motion status, and the pose, to know which waypoint the arm
is heading for. Time comes from injected `now` and `sleep`, so tests run on the simulator's FakeClock.

Waypoint actions (DO, gripper) run stop-and-set: the plan ends a blended group at a waypoint with actions,
and they are sent once the arm is there. A controller that takes them inside one blended `/run/*` request
(PULSE 1.8) plugs in as a `BlendedPath`: the plan then keeps such groups whole and `run_path` sends them.

A recorded path (a Path step's run) always goes as one `/run/linear/positions` request
(pendant.program.blended); on a controller without it (404) it plays stop-and-go, one linear move per
waypoint, and `notice` tells the page. Interrupted, it resumes at the waypoint it was heading for: from where
the arm stopped (on the path), straight to that waypoint, then blended through the rest.

A planned Move J asks its `PathPlanner` (pendant.planning.live.ControllerPlanner, given by whoever builds the
runner: program sits below planning) for a path from where the arm is to its target, in the cell as it is
then, and runs the waypoints as one /run/joint/poses along the checked segments (blended.run_planned_path);
its actions follow stop-and-set. Interrupted, it plans again on resume, from where the arm stopped.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from pendant.controller import Controller, ControllerError, MotionStatus
from pendant.controller.errors import Emergency, Unsupported
from pendant.controller.types import DEFAULT_GRIPPER_TIMEOUT_MS, Pose, Position, SignalLevel
from pendant.program.blended import FALLBACK_NOTE, BlendedRun, run_planned_path
from pendant.program.models import (
    GripperAction,
    GripperAtWaypoint,
    GripperStep,
    OutputAction,
    OutputStep,
    WaitInputStep,
    WaitStep,
    WaypointAction,
)
from pendant.program.plan import MoveGroup, Single, Target

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

# The stops the controller reports itself (a protective stop or a fault shows as ERROR): a run that meets
# one ends "Stopped at step N by the controller (...)", as after any stop; MOTION_FAILED stays a failure.
STOPPED_BY_CONTROLLER = {
    MotionStatus.ERROR: "the controller (ERROR: a protective stop or a fault)",
    MotionStatus.EMERGENCY: "the controller (EMERGENCY)",
    MotionStatus.ZERO_GRAVITY: "the controller (the arm relaxed, ZERO_GRAVITY)",
}


MSG_NO_PLANNER = "this run cannot plan around obstacles (no planner was given to it)"


class PathPlanner(Protocol):
    """Joint waypoints (degrees) from where the arm is to `goal`, around the controller's obstacles, the
    last one reaching `goal`; ControllerError saying why there is none. `cancelled()` ends the search."""

    def __call__(
        self, controller: Controller, goal: Pose | Position, cancelled: Callable[[], bool]
    ) -> list[Pose]: ...


class BlendedPath(Protocol):
    """A controller that runs a group with per-waypoint blend radii and actions in one `/run/*` request."""

    def run_path(self, group: MoveGroup) -> None: ...


class Interrupted(Exception):
    """Pause or stop arrived; `target` is the waypoint of the group to resume at."""

    def __init__(self, target: int = 0) -> None:
        self.target = target


class StepFailed(Exception):
    """The node failed at `target` (its line); `whole` when the controller refused a blended group whole;
    `stopped_by`: the controller stopped the arm itself (STOPPED_BY_CONTROLLER's words), not a failure."""

    def __init__(self, reason: str, target: int = 0, whole: bool = False, stopped_by: str = "") -> None:
        self.reason = reason
        self.target = target
        self.whole = whole
        self.stopped_by = stopped_by


@dataclass
class Timing:
    sleep: Callable[[float], object]
    now: Callable[[], float]
    poll_s: float = POLL_S


class NodeExecutor:
    """Runs nodes on `controller`; `interrupted()` says a pause or stop was asked for (checked in waits)."""

    def __init__(
        self,
        controller: Controller,
        timing: Timing,
        interrupted: Callable[[], bool],
        freeze: Callable[[], None],
        blended: BlendedPath | None = None,
        notice: Callable[[str], None] = lambda text: None,
        planner: PathPlanner | None = None,
        before_send: Callable[[], None] = lambda: None,
    ) -> None:
        self._controller = controller
        self._before_send = before_send  # collects stops on their way (`pendant run`'s poll)
        self._tolerated: MotionStatus | None = None  # the stop state the run (re)started in, if any
        self._t = timing
        self._interrupted = interrupted
        self._freeze = freeze
        self._blended = blended
        self._paths = BlendedRun(controller)  # recorded paths, whatever `blended` is
        self._notice = notice
        self._planner = planner

    def begin(self) -> None:
        """A run starts or goes on (Run, Resume, Retry, Skip): a stop or failure state the controller is in
        now is the operator's to judge (its first command goes out as pressed, and the controller answers
        it); one that comes after this, a planned move's search included, is a stop."""
        try:
            status: MotionStatus | None = self._controller.get_motion_status()
        except ControllerError:
            status = None  # the first command's own look says why
        self._tolerated = status if status in FAILED_STATES else None

    def check(self, target: int = 0) -> None:
        if self._interrupted():
            raise Interrupted(target)

    def command(self, target: int, send: Callable[[], object]) -> None:
        """Send a command unless interrupted, or unless the controller stopped the arm itself since the run
        (re)started or took its last command (an arm another client relaxed is not moved off on); if an
        interrupt raced it, freeze again so it does not run."""
        self._before_send()
        self.check(target)
        status = self._controller.get_motion_status()
        if status is not self._tolerated:
            _raise_if_failed(status, target)
        send()
        self._tolerated = None  # the controller has taken a command since: any stop from now on is one
        if self._interrupted():
            self._freeze()
            raise Interrupted(target)

    def controller_still_well(self, target: int = 0) -> None:
        """A step that does not move the arm still ends when the controller reports a stop of its own (a
        protective stop, an emergency, the arm relaxed) rather than going on to the next motion."""
        _raise_if_failed(self._controller.get_motion_status(), target)

    # --- conditions ----------------------------------------------------------------------------------
    def input_is(self, port: int, level: SignalLevel) -> bool:
        try:
            return self._controller.get_input(port) is level
        except ControllerError as error:
            raise _refused(error) from error

    # --- single steps --------------------------------------------------------------------------------
    def single(self, node: Single) -> None:
        try:
            self._single(node)
        except ControllerError as error:
            raise _refused(error) from error

    def _single(self, node: Single) -> None:
        controller, step = self._controller, node.step
        match step:
            case GripperStep():
                self._gripper(step.action, step.timeout_ms)
            case OutputStep():
                self.controller_still_well()
                self.command(0, lambda: controller.set_output(step.port, step.level))
            case WaitInputStep():
                started = self._t.now()
                while True:
                    self.check()
                    self.controller_still_well()
                    if controller.get_input(step.port) is step.level:
                        return
                    if self._t.now() - started >= step.timeout_ms / 1000.0:
                        raise StepFailed(
                            f"DI{step.port} did not go {step.level.value} within {step.timeout_ms} ms"
                        )
                    self._t.sleep(self._t.poll_s)
            case WaitStep():
                ends_at = self._t.now() + step.ms / 1000.0
                while (left := ends_at - self._t.now()) > 0:
                    self.check()  # a paused wait starts over on resume
                    self.controller_still_well()
                    self._t.sleep(min(self._t.poll_s, left))

    def _gripper(self, action: GripperAction, timeout_ms: int, target: int = 0) -> None:
        controller = self._controller
        gripper = controller.open_gripper if action is GripperAction.OPEN else controller.close_gripper
        started = self._t.now()
        self.command(target, lambda: gripper(timeout_ms))
        # The arm stays put while the gripper works: wait out the timeout and any queued motion.
        while True:
            self.check(target)
            status = controller.get_motion_status()
            _raise_if_failed(status, target)
            if self._t.now() - started >= timeout_ms / 1000.0 and status is not MotionStatus.RUNNING:
                return
            self._t.sleep(self._t.poll_s)

    # --- moves ---------------------------------------------------------------------------------------
    def move(self, group: MoveGroup, start: int, only_one: bool, heading: Callable[[int], None]) -> int:
        """Run targets[start:] (only targets[start] when `only_one`), then the last one's actions; returns
        the index of the last target reached. `heading(k)` is told which target the arm is heading for.
        A recorded path runs whole (a Step plays all of it)."""
        if group.path:
            return self._path(group, start, heading)
        if group.planned:
            return self._planned(group, heading)
        end = start + 1 if only_one else len(group.targets)
        targets = group.targets[start:end]
        try:
            self._move(group, targets, start, heading)
        except ControllerError as error:
            raise _refused(error, start, whole=len(targets) > 1) from error
        if self._blended is None:
            for action in targets[-1].actions:
                self._action(action, end - 1)
        return end - 1

    def _path(self, group: MoveGroup, start: int, heading: Callable[[int], None]) -> int:
        """targets[start:] of a recorded path: one blended run, or stop-and-go without /run/*."""
        last = len(group.targets) - 1
        at = start
        try:
            if self._paths.supported is not False:
                try:
                    self._move(group, group.targets[start:], start, heading, self._paths.run_path)
                    return last
                except Unsupported:
                    self._notice(FALLBACK_NOTE)
            for at in range(start, last + 1):
                self._move(group, (group.targets[at],), at, heading, self._one_linear_move)
        except ControllerError as error:
            raise _refused(error, at) from error
        return last

    def _planned(self, group: MoveGroup, heading: Callable[[int], None]) -> int:
        """A planned Move J (one target): plan from here, run the path in one request, then its actions."""
        target = group.targets[0]
        goal = target.pose if target.pose is not None else target.position
        assert goal is not None
        self.check()
        if self._planner is None:
            raise StepFailed(MSG_NO_PLANNER)
        heading(0)
        try:
            via = self._planner(self._controller, goal, self._interrupted)
        except ControllerError as error:
            self.check()  # a pause or stop ended the search: not a failure
            raise StepFailed(f"no path around the obstacles to {target.name}: {error.message}") from error
        controller = self._controller
        try:
            self._move(group, (target,), 0, heading, lambda _: run_planned_path(controller, via, group.speed))
            for action in target.actions:
                self._action(action, 0)
        except ControllerError as error:
            raise _refused(error) from error
        return 0

    def _one_linear_move(self, group: MoveGroup) -> None:
        positions = [t.expect_position() for t in group.targets]
        self._controller.run_positions(positions, group.params)

    def _move(
        self,
        group: MoveGroup,
        targets: tuple[Target, ...],
        first: int,
        heading: Callable[[int], None],
        send: Callable[[MoveGroup], object] | None = None,
    ) -> None:
        controller, blended = self._controller, self._blended
        joint = group.by_angles
        start = self._reading(joint)
        points = [_point_of(t) for t in targets]
        sub = MoveGroup(targets, group.motion, group.speed, group.velocity_m_s)
        if send is not None:
            self.command(first, lambda: send(sub))
        elif blended is not None:
            self.command(first, lambda: blended.run_path(sub))
        elif joint:
            poses = [t.expect_pose() for t in targets]
            self.command(first, lambda: controller.run_poses(poses, group.params))
        else:
            positions = [t.expect_position() for t in targets]
            self.command(first, lambda: controller.run_positions(positions, group.params))
        tol = ARRIVAL_TOL_DEG if joint else ARRIVAL_TOL_M
        issued_at = self._t.now()
        seen_running = False
        towards = 0
        while True:
            self.check(first + towards)
            try:
                status = controller.get_motion_status()
                here = self._reading(joint)
            except ControllerError as error:
                raise _refused(error, first + towards) from error
            towards = max(towards, _heading(start, points, here))
            heading(first + towards)
            _raise_if_failed(status, first + towards)
            if status is MotionStatus.RUNNING:
                seen_running = True
            elif status is MotionStatus.IDLE:
                if _distance(here, points[-1], joint) <= tol:
                    return
                if seen_running or self._t.now() - issued_at > START_GRACE_S:
                    name = targets[towards].name
                    raise StepFailed(f"the arm stopped before reaching {name}", first + towards)
            self._t.sleep(self._t.poll_s)

    def _action(self, action: WaypointAction, target: int) -> None:
        try:
            if isinstance(action, OutputAction):
                self.command(target, lambda: self._controller.set_output(action.port, action.value))
            elif isinstance(action, GripperAtWaypoint):
                self._gripper(action.value, DEFAULT_GRIPPER_TIMEOUT_MS, target)
        except ControllerError as error:
            raise _refused(error, target) from error

    def _reading(self, joint: bool) -> np.ndarray:
        """Where the arm is, in the space the group moves in: angles (degrees) or TCP point (metres)."""
        if joint:
            return np.asarray(self._controller.get_pose().angles, dtype=float)
        p = self._controller.get_position().point
        return np.array([p.x, p.y, p.z])


def _refused(error: ControllerError, target: int = 0, whole: bool = False) -> StepFailed:
    """A command or read the controller refused; an emergency stop is the controller's stop, not a failure."""
    stopped_by = STOPPED_BY_CONTROLLER[MotionStatus.EMERGENCY] if isinstance(error, Emergency) else ""
    return StepFailed(error.message, target, whole, stopped_by)


def _raise_if_failed(status: MotionStatus, target: int) -> None:
    if status in FAILED_STATES:
        raise StepFailed(FAILED_STATES[status], target, stopped_by=STOPPED_BY_CONTROLLER.get(status, ""))


def _point_of(target: Target) -> np.ndarray:
    if target.pose is not None:
        return np.asarray(target.pose.angles, dtype=float)
    assert target.position is not None
    p = target.position.point
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
