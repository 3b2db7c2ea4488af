"""What the banner says, read from the controller's state and the program runner's: what happened, since when,
and the one or two actions that get the operator going again, in order.

`banner_view` is a pure function of one reading; `Recovery` keeps the shared view for every browser, notes
since when each cause has lasted, writes each new cause to the event log once, and names what a failed
program step would have hit (the controller says only "Collision detected").
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from enum import StrEnum

import numpy as np

from pendant.cell.collision_names import explain_collision
from pendant.cell.geometry import CellModel
from pendant.controller import MotionStatus
from pendant.controller.system_types import FailureType, SystemState
from pendant.eventlog import EventKind, EventLog
from pendant.kinematics import ArmModel
from pendant.program import MoveStep, Program, RunProgress, RunState
from pendant.program.tree import lines
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.snapshot import Snapshot

MSG_RELEASE_EMERGENCY = "Release the emergency stop on the arm, then Recover"
MSG_RELEASE_EMERGENCY_SIM = "In the simulator: Reset simulator (keeps the cell)"
MSG_NOT_RESPONDING = "Check the controller's power and cable; the page reconnects by itself"
MSG_OFFLINE = "The pendant cannot reach the controller; it reconnects by itself"


class Action(StrEnum):
    """What a banner button does (the label is the view's: it names the step)."""

    RECOVER = "recover"
    RETRY = "retry"
    RESUME = "resume"
    SKIP = "skip"
    STOP_PROGRAM = "stop program"
    SIM_RESET = "sim reset"
    LEAVE_FREE_DRIVE = "leave free drive"
    FINISH_UNTWISTING = "finish untwisting"


@dataclass(frozen=True)
class BannerView:
    """One non-normal state: `title` (what), `detail` (the controller's reason, the obstacle, the step),
    `next_step` (in words), `actions` (buttons, in the order to press them) with their `labels`."""

    key: str  # the cause; a new key is a new cause (its own "since")
    title: str
    detail: str
    next_step: str
    actions: tuple[Action, ...] = ()
    labels: tuple[str, ...] = ()
    colour: str = "#e03131"
    since: float = 0.0  # wall clock (time.time) the cause was first seen
    failed_step: int | None = None  # 0-based line of a failed program step

    def label(self, action: Action) -> str:
        return self.labels[self.actions.index(action)]


def _newest_failure(state: CellState) -> str:
    return state.failures[-1].message if state.failures else ""


def _controller_view(snapshot: Snapshot, state: CellState, simulator: bool) -> BannerView | None:
    status = snapshot.motion_status
    reason = _newest_failure(state)
    if status is None:
        if not snapshot.online:
            return BannerView(
                "offline", "Controller offline", snapshot.error or "", MSG_OFFLINE, colour="#868e96"
            )
        actions = (Action.SIM_RESET,) if simulator else ()
        words = MSG_RELEASE_EMERGENCY_SIM if simulator else MSG_NOT_RESPONDING
        return BannerView("no response", "Controller not responding", snapshot.error or "", words, actions)
    if status is MotionStatus.EMERGENCY:
        actions = (Action.SIM_RESET,) if simulator else (Action.RECOVER,)
        words = (
            f"{MSG_RELEASE_EMERGENCY}. {MSG_RELEASE_EMERGENCY_SIM}" if simulator else MSG_RELEASE_EMERGENCY
        )
        detail = snapshot.error or reason
        return BannerView("emergency", "EMERGENCY", detail, words, actions, colour="#c92a2a")
    if status is MotionStatus.ZERO_GRAVITY:
        words = "The arm is relaxed and moves by hand: leave free drive to jog or run"
        return BannerView("free drive", "Free drive", "", words, (Action.LEAVE_FREE_DRIVE,), colour="#9c36b5")
    if status is MotionStatus.MOTION_FAILED:
        return BannerView("motion failed", "Motion failed", reason, "Recover, then go on", (Action.RECOVER,))
    if status is not MotionStatus.ERROR:
        return None
    if state.system_state is SystemState.TWISTED:
        words = "Unwind the cable by hand (free drive), then Finish untwisting"
        return BannerView("twisted", "Cable twisted", reason, words, (Action.FINISH_UNTWISTING,))
    if state.failures and state.failures[-1].type is FailureType.STOP_2:
        return BannerView(
            "protective stop",
            "Protective stop",
            reason,
            "Recover to continue",
            (Action.RECOVER,),
            colour="#e8590c",
        )
    detail = reason or snapshot.error or ""
    return BannerView("error", "Controller error", detail, "Recover to continue", (Action.RECOVER,))


def banner_view(
    snapshot: Snapshot, state: CellState, progress: RunProgress, *, simulator: bool, can_resume: bool
) -> BannerView | None:
    """The banner for one reading (None: all is well). A fault of the controller comes first; a failed
    program step's Retry and Skip follow once the controller is back (Stop program is always offered)."""
    controller = _controller_view(snapshot, state, simulator)
    # A failed step, or a run ended by a stop heard elsewhere: both keep their place for Retry or Skip.
    failed = progress.state in (RunState.FAILED, RunState.STOPPED) and progress.failed_step is not None
    step = (progress.failed_step or 0) + 1
    if controller is not None:
        if not failed or controller.key == "offline":
            return controller
        return replace(
            controller,
            detail=f"{controller.detail} · {progress.message}" if controller.detail else progress.message,
            next_step=f"{controller.next_step}; then Retry or Skip step {step}",
            actions=(*controller.actions, Action.STOP_PROGRAM),
            failed_step=progress.failed_step,
        )
    if not failed:
        return _paused_view(progress, can_resume)
    actions = (Action.RETRY, Action.SKIP, Action.STOP_PROGRAM) if can_resume else (Action.STOP_PROGRAM,)
    if not can_resume:
        words = "Stop the program"
    elif progress.state is RunState.STOPPED:
        words = "When it is safe, Retry the step, or Skip it"
    else:
        words = "Fix the cause, then Retry the step, or Skip it"
    return BannerView(
        "program",
        f"Program stopped at step {step}",
        progress.message,
        words,
        actions,
        failed_step=progress.failed_step,
    )


def _paused_view(progress: RunProgress, can_resume: bool) -> BannerView | None:
    """A run paused for a reason the operator did not give (their page closed): every browser is told."""
    if progress.state is not RunState.PAUSED or not progress.paused_because:
        return None
    actions = (Action.RESUME, Action.STOP_PROGRAM) if can_resume else (Action.STOP_PROGRAM,)
    return BannerView(
        "paused",
        f"Program paused at step {(progress.step_index or 0) + 1}",
        progress.paused_because,
        "The arm is held. An operator with control can Resume or Stop the program",
        actions,
        colour="#e8590c",
    )


def labelled(view: BannerView) -> BannerView:
    """The buttons' words: the step they act on is named ("Retry step 7")."""
    step = (view.failed_step or 0) + 1
    words = {
        Action.RECOVER: "Recover",
        Action.RETRY: f"Retry step {step}",
        Action.RESUME: "Resume program",
        Action.SKIP: f"Skip step {step}",
        Action.STOP_PROGRAM: "Stop program",
        Action.SIM_RESET: "Reset simulator (keeps the cell)",
        Action.LEAVE_FREE_DRIVE: "Leave free drive",
        Action.FINISH_UNTWISTING: "Finish untwisting",
    }
    return replace(view, labels=tuple(words[a] for a in view.actions))


class Recovery:
    """The one banner view every browser shows, and the event log's record of each cause."""

    def __init__(
        self,
        events: EventLog,
        arm: ArmModel,
        *,
        simulator: bool,
        cell: Callable[[], CellModel | None] = lambda: None,
        current_q: Callable[[], np.ndarray | None] = lambda: None,
        clock: Callable[[], float] = time.time,
    ) -> None:
        self._events = events
        self._arm = arm
        self._cell = cell
        self._current_q = current_q
        self._clock = clock
        self.simulator = simulator
        self.view: BannerView | None = None
        self.refused_q: np.ndarray | None = None  # the pose of the failed step (a red ghost), if a move
        self.refused_obstacles: tuple[str, ...] = ()

    def update(
        self, snapshot: Snapshot, state: CellState, progress: RunProgress, *, can_resume: bool
    ) -> BannerView | None:
        view = banner_view(snapshot, state, progress, simulator=self.simulator, can_resume=can_resume)
        if view is not None:
            previous = self.view
            ongoing = previous is not None and previous.key == view.key  # a reason read later: same since
            view = labelled(replace(view, since=previous.since if ongoing and previous else self._clock()))
            if not ongoing or (previous is not None and previous.detail != view.detail):
                cause = f"{view.title}: {view.detail}" if view.detail else view.title
                self._events.record(EventKind.ERROR, "banner", f"{cause} (next: {view.next_step})")
        elif self.view is not None:
            self._events.record(EventKind.STATE, "banner", f"{self.view.title} cleared")
        if view is None or view.failed_step is None:
            self.refused_q, self.refused_obstacles = None, ()
        self.view = view
        return view

    def explain_step_failure(self, program: Program, first: int, last: int, reason: str) -> str:
        """The runner's hook: a bare collision of a move (or of a blended group of moves, lines `first` to
        `last`) gets what is in the way named, and the red ghost of that pose (with the obstacles it hits)
        is kept for the banner to draw."""
        listed = lines(program.steps)
        q_from = self._current_q()
        cell = self._cell()
        for line in range(first, min(last, len(listed) - 1) + 1):
            step = listed[line].step
            if not isinstance(step, MoveStep) or step.offset is not None:
                continue
            try:
                q = np.radians(np.asarray(program.waypoint(step.waypoint).pose.angles, dtype=float))
            except KeyError:
                continue
            named = explain_collision(reason, self._arm, q, cell, q_from)
            if named.reason == reason:
                return reason  # not a bare collision: nothing to name
            if named.obstacles or (named.reason is not None and " would touch " in named.reason):
                self.refused_q, self.refused_obstacles = q, named.obstacles
                return named.reason or reason
            q_from = q
        return reason  # the page's model finds nothing in the way (the controller samples finer)
