"""Plan around: when the straight move to the target would collide, a path around the obstacles.

The planner (pendant.planning, OMPL over the one cell check) runs on the command worker, never on the UI
thread, against the controller's cell as it is then; its answer is drawn as the TCP's course and played by
the translucent ghost. Move sends it as one /poses/run at the Move speed, with the TCP held to the manual-mode
250 mm/s, and only from where it was planned. Freeze (any browser) ends a search under way and drops what it
would have found; it stops the motion as it stops every motion.
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from typing import Protocol

import numpy as np
import viser

from pendant.controller import Controller
from pendant.controller.errors import MSG_COLLISION, PreconditionFailed
from pendant.kinematics import ArmModel
from pendant.kinematics.cell_check import joint_samples
from pendant.planning.joint_planner import DEFAULT_BUDGET_S, PlannedPath
from pendant.planning.live import as_poses, plan_on
from pendant.planning.request import PlanTarget
from pendant.program.blended import run_planned_path
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.typed_field import FieldInvalid, NumberField
from pendant.ui.scene.course import CourseLine
from pendant.ui.target.check import TargetCheck

COURSE_STEP_RAD = math.radians(2.0)  # the drawn course: a TCP point at least every 2 degrees per joint
PLAYBACK_S = 2.5  # the ghost plays the path in this long, whatever its length
PLAYBACK_FPS = 20.0
# Move runs the plan only from where it was made: further than this (any joint) and it must be made again.
START_TOL_RAD = math.radians(0.5)
GOAL_TOL_RAD = 1e-9  # the plan's last waypoint is the target's angles, through degrees and back
MSG_MOVED = "the arm has moved since the path was planned: press Plan around again"
MSG_PLANNING = "Planning a path around the obstacles…"
MSG_CANCELLED = "Plan around cancelled by a stop."


class PlanHost(Protocol):
    """What the section needs of the Target panel."""

    check: TargetCheck
    speed: NumberField
    locked: bool

    def show_planned_ghost(self, q: np.ndarray) -> None: ...

    def plan_played(self) -> None: ...


def needs_plan(check: TargetCheck) -> bool:
    """A target the arm can reach but not by the straight move: the target or the path to it collides."""
    return check.q is not None and check.reason is not None and check.reason.startswith(MSG_COLLISION)


class PlanSection:
    def __init__(
        self,
        target: GuiTarget,
        arm: ArmModel,
        runner: CommandRunner,
        host: PlanHost,
        current_tool: Callable[[], np.ndarray],
        budget_s: float = DEFAULT_BUDGET_S,
    ) -> None:
        self._arm = arm
        self._runner = runner
        self._host = host
        self._current_tool = current_tool
        self.budget_s = budget_s
        self._lock = threading.Lock()
        self._asked: object | None = None  # the plan request under way (a newer one replaces it)
        self.path: PlannedPath | None = None  # the plan Move would run
        self._course = CourseLine(target.scene, "/planned_course")
        self.plan_button = target.gui.add_button(
            "Plan around", icon=viser.Icon.ROUTE, visible=False, hint="Find a path around the obstacles"
        )
        self.move_button = target.gui.add_button("Move", visible=False, hint="Run the planned path")
        self.status = target.gui.add_markdown("")
        self.plan_button.on_click(lambda event: self.plan(event.client))
        self.move_button.on_click(lambda event: self.run(event.client))

    # --- planning ----------------------------------------------------------------------------------
    def plan(self, client: viser.ClientHandle | None = None) -> Future[object] | None:
        """Search a path to the target on the command worker; None when the target needs none."""
        check = self._host.check
        if not needs_plan(check) or check.q is None:
            return None
        goal = check.q.copy()
        asked = object()
        stops = self._runner.stops_sent
        with self._lock:
            self._asked = asked
            self._forget_path()
        self._say(MSG_PLANNING)
        self.plan_button.disabled = True
        target = PlanTarget(angles=[float(a) for a in np.degrees(goal)])
        budget = self.budget_s

        def search(controller: Controller) -> PlannedPath:
            return plan_on(
                controller,
                self._arm,
                target,
                budget_s=budget,
                cancelled=lambda: self._runner.stops_sent != stops,
            )

        future = self._runner.submit("Plan around", search, client)
        future.add_done_callback(lambda done: self._planned(done, asked, goal, stops))
        return future

    def _planned(self, done: Future[object], asked: object, goal: np.ndarray, stops: int) -> None:
        with self._lock:
            if self._asked is not asked:  # the target changed, or another plan was asked for
                return
            self._asked = None
            self.plan_button.disabled = self._host.locked
            if self._runner.stops_sent != stops:
                self._say(MSG_CANCELLED)
                return
            problem = done.exception()
            if problem is not None:
                self._say(f"**Cannot plan:** {getattr(problem, 'message', None) or problem}")
                return
            path = done.result()
            assert isinstance(path, PlannedPath)
            if self._host.check.q is None or not np.array_equal(self._host.check.q, goal):
                return
            self.path = path
            self.move_button.visible = True
            self.move_button.disabled = self._host.locked
        corners = len(path.waypoints) - 2
        self._say(
            f"**Path planned** around the obstacles: {corners} corner(s), "
            f"{math.degrees(path.length_rad):.0f}° of joint travel, found in {path.planning_s:.2f} s. "
            "Move runs it."
        )
        samples = _densified(path.waypoints)
        tool = self._current_tool()
        self._course.show(np.array([(self._arm.fk(q) @ tool)[:3, 3] for q in samples]))
        threading.Thread(target=self._play, args=(path, samples), daemon=True, name="plan-ghost").start()

    def _play(self, path: PlannedPath, samples: np.ndarray) -> None:
        """The ghost along the path, then at rest at the target (unless the plan is dropped meanwhile)."""
        picks = np.linspace(0, len(samples) - 1, max(2, int(PLAYBACK_S * PLAYBACK_FPS))).round().astype(int)
        for index in picks:
            with self._lock:  # refresh() drops the path under it: no frame lands after the target changed
                if self.path is not path:
                    return
                self._host.show_planned_ghost(samples[index])
            time.sleep(1.0 / PLAYBACK_FPS)
        with self._lock:
            if self.path is path:
                self._host.plan_played()  # a finished playback leaves the target's ghost, named so

    # --- running -----------------------------------------------------------------------------------
    def run(self, client: viser.ClientHandle | None = None) -> Future[object] | None:
        """Send the planned path as one /poses/run; refused (by the worker) if the arm has moved since."""
        path = self.path
        if path is None:
            return None
        try:
            speed = self._host.speed.value
        except FieldInvalid as error:
            notify_refusal(client, "Move (planned) refused", error.message)
            return None
        poses = as_poses(path)
        start = path.waypoints[0]

        def send(controller: Controller) -> None:
            here = np.radians(controller.get_pose().angles)
            if float(np.max(np.abs(here - start))) > START_TOL_RAD:
                raise PreconditionFailed(MSG_MOVED)
            run_planned_path(controller, poses, speed)

        return self._runner.submit("Move (planned)", send, client, motion=True)

    # --- following the target ---------------------------------------------------------------------
    def refresh(self, check: TargetCheck) -> None:
        """The target or the cell changed: a plan to another target (or in another cell) is dropped."""
        with self._lock:
            goal = None if self.path is None else self.path.waypoints[-1]
            if goal is not None and (check.q is None or not np.allclose(goal, check.q, atol=GOAL_TOL_RAD)):
                self._forget_path()
                self._say("")
            offered = needs_plan(check)
            if self.plan_button.visible != offered:
                self.plan_button.visible = offered
            self.plan_button.disabled = self._host.locked or self._asked is not None
            self.move_button.disabled = self._host.locked
            if not offered and self._asked is None and self.path is None:
                self._say("")

    def forget(self) -> None:
        """Drop the plan and any search under way (the cell changed: it must be made again)."""
        with self._lock:
            self._asked = None
            self._forget_path()
            self.plan_button.disabled = self._host.locked
            self._say("")

    def _forget_path(self) -> None:
        self.path = None
        self.move_button.visible = False
        self._course.hide()

    def _say(self, text: str) -> None:
        if self.status.content != text:
            self.status.content = text

    @property
    def course_shown(self) -> bool:
        return self._course.shown


def _densified(waypoints: np.ndarray) -> np.ndarray:
    """The joint path's configurations at most COURSE_STEP_RAD apart per joint, corners included."""
    return np.concatenate([joint_samples(a, b, COURSE_STEP_RAD) for a, b in itertools.pairwise(waypoints)])
