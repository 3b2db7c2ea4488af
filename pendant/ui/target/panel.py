"""Drag to target: a gizmo at the TCP and typed joint angles pose a ghost arm; Move J / Move L run it."""

from __future__ import annotations

import math
import threading
from collections.abc import Callable
from concurrent.futures import Future

import numpy as np
import viser
import viser.transforms as vtf

from pendant.cell.geometry import CellModel
from pendant.controller import Controller, MotionParams, MotionType, Pose, Position
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import inverse, matrix_to_position, position_to_matrix
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.typed_field import FieldInvalid, NumberField, read_all
from pendant.ui.scene.cell import ObstacleDrawing
from pendant.ui.scene.ghost_stage import GhostStage
from pendant.ui.scene.shared_urdf import SharedUrdf
from pendant.ui.target.check import TargetCheck, check_flange_target, check_joint_target
from pendant.ui.target.hand_guide import HandGuide
from pendant.ui.target.plan_section import PlanSection, needs_plan

GHOST_OK_RGBA = (0.25, 0.55, 1.0, 0.35)
GHOST_BAD_RGBA = (0.95, 0.15, 0.15, 0.45)
GIZMO_SCALE = 0.18
# While the arm moves the gizmo waits here, far beyond the view (see follow()).
GIZMO_PARKED_M = (0.0, 0.0, -1.0e4)
DEFAULT_MOVE_SPEED_PERCENT = 20.0
REACHED_TOL_RAD = 1e-3  # the arm at rest this close to the target has reached it (0.06°)
REST_TOL_RAD = 1e-6  # the arm at rest where the target was last checked from: nothing to check again


class TargetPanel:
    """The target the operator is preparing; never moves the arm until Move J or Move L is pressed.

    Until the operator sets a target (drags the gizmo, types a joint angle), the target follows the arm: no
    ghost, nothing to run, and no stale target left behind where the arm was when the page opened.
    """

    def __init__(
        self,
        target: GuiTarget,
        arm: ArmModel,
        runner: CommandRunner,
        current_q: Callable[[], np.ndarray | None],
        current_tool: Callable[[], np.ndarray],
        current_cell: Callable[[], CellModel | None] = lambda: None,
        ghosts: GhostStage | None = None,
    ) -> None:
        self._arm = arm
        self._current_cell = current_cell  # the controller's obstacles and tool shape, as last read
        self.hand: HandGuide | None = None  # simulator: in free drive, a target moves the arm by hand
        self._runner = runner
        self._current_q = current_q
        self._current_tool = current_tool  # T_flange_tcp: the gizmo holds the tool's TCP, as /position does
        self._ghosts = {
            ok: SharedUrdf(
                target,
                arm.urdf_path,
                root_node_name=f"/ghost_{'ok' if ok else 'bad'}",
                mesh_color_override=GHOST_OK_RGBA if ok else GHOST_BAD_RGBA,
            )
            for ok in (True, False)
        }
        self._hits = ObstacleDrawing(target.scene, "/ghost_hits", only_touching=True)
        # One ghost at a time in the view (scene/ghost_stage.py): the target's and the plan's are this one.
        self.ghosts = ghosts if ghosts is not None else GhostStage()
        self._ghost_off = False  # another ghost took the view: this one waits for the operator's next target
        hide = self._hide_ghost
        self.ghosts.register("target", hide)
        self.ghosts.register("plan", hide)
        self._gizmo = target.scene.add_transform_controls("/target", scale=GIZMO_SCALE, visible=False)
        self._syncing = False
        # The operator's edits (viser's thread pool) and the refresh's rechecks (a new cell) take turns: a
        # check made against the old cell must not land after the recheck against the new one.
        self._checking = threading.RLock()
        self._locked = False  # a viewer's page: Move J / Move L stay disabled whatever the target
        self.check = TargetCheck(None, "No target yet")
        self.following = True  # the target is where the arm is (see the class doc)
        self._ghost_q: np.ndarray | None = None  # where the ghost stands: the last target IK could solve
        self.ghost_shown: bool | None = None  # True: the blue (executable) ghost, False: the red one
        self._checked_from: np.ndarray | None = None  # where the arm was when the target was last checked

        self.reason = target.gui.add_markdown("Drag the gizmo or type joint angles to set a target.")
        # Typed, committed on Enter or leaving the box (kit/typed_field.py): the ghost and Move J use the
        # number typed, and a box left empty or with letters refuses Move J with the reason.
        self.joints = [
            NumberField(
                target.gui,
                f"J{i + 1} °",
                0.0,
                low=math.floor(math.degrees(arm.lower[i]) * 10) / 10,
                high=math.ceil(math.degrees(arm.upper[i]) * 10) / 10,
                name=f"J{i + 1}",
            )
            for i in range(6)
        ]
        self.speed = NumberField(
            target.gui, "Move speed %", DEFAULT_MOVE_SPEED_PERCENT, low=1.0, high=100.0, decimals=0
        )
        self.from_current = target.gui.add_button("Target = current", icon=viser.Icon.TARGET)
        self.move_j = target.gui.add_button("Move J", disabled=True)
        self.move_l = target.gui.add_button("Move L", disabled=True)
        # The boxes' text when the target was last set from them or shown in them: other text at Move J is a
        # commit whose check has not run yet (viser runs callbacks on a pool, the click's may come first).
        self._shown_texts = self._typed_texts()
        self.plan = PlanSection(target, arm, runner, self, current_tool)
        self._show_ghost(self.check)

        @self._gizmo.on_update
        def _(event: viser.TransformControlsEvent) -> None:
            if self._syncing:
                return
            T_base_tcp = vtf.SE3.from_rotation_and_translation(
                vtf.SO3(np.asarray(self._gizmo.wxyz)), np.asarray(self._gizmo.position)
            ).as_matrix()
            self.set_tcp_target(T_base_tcp, event.client)

        for field in self.joints:
            field.on_commit(lambda event: self._joints_typed(event.client))
        self.from_current.on_click(lambda _: self.reset_to_current())
        self.move_j.on_click(lambda event: self.run(MotionType.JOINT, event.client))
        self.move_l.on_click(lambda event: self.run(MotionType.LINEAR, event.client))

    # --- setting the target -------------------------------------------------------------------------
    @property
    def executable(self) -> bool:
        """A target the operator set, and that can be run."""
        return self.check.ok and not self.following

    def reset_to_current(self) -> None:
        """Drop the operator's target: the target follows the arm again."""
        with self._checking:
            self.following = True
            q = self._current_q()
            if q is not None:
                self._target_joints(q)

    def follow(self, q: np.ndarray | None, *, moving: bool) -> None:
        """The arm is at `q` now: the target moves with it unless the operator has set one. While the arm
        moves the gizmo is hidden rather than chased (six boxes and a gizmo to every browser, 5 times a
        second); it comes back at the TCP when the arm stops."""
        if q is None:
            return
        if not self.following:
            if not moving:
                self._arrived(q)
            return
        if moving:
            if self.gizmo_shown:
                # Parked out of the view, not made invisible: viser unmounts an invisible gizmo, and the
                # page then compiles its shader programs again when it comes back; in software WebGL each
                # compile waits for the frame being drawn (a 50-90 ms long task at each press and release).
                # Shrinking it still remade its lines' programs.
                self._gizmo.position = GIZMO_PARKED_M
        elif self.check.q is None or not np.array_equal(self.check.q, q) or not self.gizmo_shown:
            with self._checking:
                if self.following:  # still: the operator may have set a target meanwhile
                    self._target_joints(q)

    def _arrived(self, q: np.ndarray) -> None:
        """The arm came to rest somewhere new: the verdict is made again from here (a target reached by a
        planned move is not "cannot execute"), and a plan from elsewhere (run, or stale: a program, a jog
        moved the arm) is cleared with its drawn path."""
        checked_from = self._checked_from
        if checked_from is not None and np.allclose(checked_from, q, atol=REST_TOL_RAD):
            return
        with self._checking:
            if self.following or self.check.q is None:
                return
            path = self.plan.path
            if path is not None and not np.allclose(path.waypoints[0], q, atol=REACHED_TOL_RAD):
                self.plan.forget()  # run (the arm is at its end) or stale (the arm left its start)
            self._target_joints(self.check.q)

    def set_flange_target(
        self, T_base_flange: np.ndarray, client: viser.ClientHandle | None = None
    ) -> TargetCheck:
        with self._checking:
            self.following = False
            self._ghost_off = False  # the operator's target: its ghost is what they asked to see
            near = self.check.q if self.check.q is not None else self._current_q()
            near = near if near is not None else 0.5 * (self._arm.lower + self._arm.upper)
            self.check = check_flange_target(
                self._arm, T_base_flange, near, self._current_cell(), self._current_q()
            )
            self._show(move_gizmo=False)
            self._guide(client)
            return self.check

    def set_tcp_target(self, T_base_tcp: np.ndarray, client: viser.ClientHandle | None = None) -> TargetCheck:
        """Where the gizmo was dragged: the tool's TCP (the flange when no tool is set)."""
        return self.set_flange_target(T_base_tcp @ inverse(self._current_tool()), client)

    def set_joint_target(self, q: np.ndarray, client: viser.ClientHandle | None = None) -> TargetCheck:
        with self._checking:
            self.following = False
            self._ghost_off = False
            check = self._target_joints(q)
            self._guide(client)
            return check

    def _joints_typed(self, client: viser.ClientHandle | None) -> None:
        """The operator committed a joint box: the target is the six numbers typed (none while one is not)."""
        try:
            q = self._joint_q()
        except FieldInvalid as error:
            with self._checking:
                self.reason.content = f"**Cannot set the target:** {error.message}"
                self.move_j.disabled = self.move_l.disabled = True
            return
        self.set_joint_target(q, client)

    def _guide(self, client: viser.ClientHandle | None) -> None:
        """In free drive the target is where the hand pulls the arm: an executable one moves it there, and
        the target follows the arm again (no ghost, nothing to run)."""
        if self.hand is None or not self.hand.active or not self.check.ok or self.check.q is None:
            return
        self.hand.move(self.check.q, client)
        self.following = True
        self._show_ghost(self.check)

    def _target_joints(self, q: np.ndarray) -> TargetCheck:
        cell = None if self.following else self._current_cell()  # the arm where it is: nothing to check
        self._checked_from = self._current_q()
        self.check = check_joint_target(self._arm, np.asarray(q, dtype=float), cell, self._checked_from)
        self._show(move_gizmo=True)
        return self.check

    def recheck(self) -> None:
        """The cell changed: check the operator's target against it again (a plan must be made again)."""
        with self._checking:
            self.plan.forget()
            if not self.following and self.check.q is not None:
                self._target_joints(self.check.q)

    @property
    def obstacles_hit(self) -> dict[str, bool]:
        """The obstacles drawn red in this browser because the ghost (or its path) hits them."""
        return self._hits.shown

    # --- running it ---------------------------------------------------------------------------------
    def run(self, motion: MotionType, client: viser.ClientHandle | None = None) -> Future[object] | None:
        """Send the target as a Move J or Move L; None when the target cannot be executed."""
        label = "Move J" if motion is MotionType.JOINT else "Move L"
        try:
            speed = self.speed.value
            if not self.following:
                with self._checking:  # a box committed just before the click: its check may not have run yet
                    q_typed = self._joint_q()
                    if self._typed_texts() != self._shown_texts:
                        self.set_joint_target(q_typed, client)
        except FieldInvalid as error:
            notify_refusal(client, f"{label} refused", error.message)
            return None
        check = self.check
        if not self.executable or check.q is None:
            return None
        params = MotionParams(speed=speed, motion_type=motion)
        q_target = check.q.copy()
        if motion is MotionType.JOINT:
            pose = Pose(angles=[float(v) for v in np.degrees(q_target)])
            return self._runner.submit("Move J", lambda c: c.set_pose(pose, params), client, motion=True)
        return self._runner.submit(
            "Move L",
            lambda c: c.set_position(self._zero_tool_target(c, q_target), params),
            client,
            motion=True,
        )

    def _zero_tool_target(self, controller: Controller, q: np.ndarray) -> Position:
        """PUT /position speaks in the zero point frame and of the tool's TCP."""
        T_base_zero = position_to_matrix(controller.get_base())
        T_flange_tool = position_to_matrix(controller.get_tool().position)
        return matrix_to_position(inverse(T_base_zero) @ self._arm.fk(q) @ T_flange_tool)

    # --- display ------------------------------------------------------------------------------------
    @property
    def locked(self) -> bool:
        return self._locked

    @locked.setter
    def locked(self, locked: bool) -> None:
        self._locked = locked
        self.plan.refresh(self.check)

    def _show(self, *, move_gizmo: bool) -> None:
        check = self.check
        self.plan.refresh(check)  # first: a plan to the former target stops playing before the ghost moves
        self._show_ghost(check)
        if self.following:
            text = "Drag the gizmo or type joint angles to set a target."
        elif check.ok and self._at_target(check.q):
            text = "**Target reached** — the arm is there."
        elif check.ok:
            text = "**Target ready** — Move J or Move L runs it."
        elif needs_plan(check):  # the target is fine, the straight way to it is not: Plan around
            text = f"**No straight path:** {check.reason}"
        else:
            text = f"**Cannot execute:** {check.reason}"
        if self.reason.content != text:
            self.reason.content = text
        self.move_j.disabled = not self.executable or self.locked
        self.move_l.disabled = not self.executable or self.locked
        if check.q is None:
            return
        self._syncing = True
        try:
            for field, value in zip(self.joints, np.degrees(check.q), strict=True):
                field.show(float(value))
            self._shown_texts = self._typed_texts()
            if move_gizmo or self._gizmo_parked:
                T = self._arm.fk(check.q) @ self._current_tool()
                self._gizmo.position = T[:3, 3]
                self._gizmo.wxyz = vtf.SO3.from_matrix(T[:3, :3]).wxyz
            self._gizmo.visible = True
        finally:
            self._syncing = False

    def _hide_ghost(self) -> None:
        """Another ghost took the view (the stage calls this): hidden until the operator sets a target."""
        self._ghost_off = True
        self.ghost_shown = None
        for ghost in self._ghosts.values():
            ghost.show_visual = False

    def _show_ghost(self, check: TargetCheck) -> None:
        """Blue at an executable target; red otherwise, at the target or, when IK has no solution (out of
        reach), where the last solvable one was, so the operator sees which drag went too far. The
        obstacles it would hit are drawn red over the shared scene, in this browser only."""
        cell = self._current_cell()
        touching = () if self.following else check.touching
        self._hits.show(cell.obstacles if cell is not None else [], touching)
        if check.q is not None:
            self._ghost_q = check.q
        q = self._ghost_q
        self.ghost_shown = None if q is None or self.following or self._ghost_off else check.ok
        if self.ghost_shown is None:
            self.ghosts.hidden("target")
            self.ghosts.hidden("plan")
        else:
            self.ghosts.show("target", blocked=not self.ghost_shown)
        for ok, ghost in self._ghosts.items():
            visible = self.ghost_shown == ok
            if visible and q is not None:  # posed first: a ghost drawn at its first show stands there
                ghost.pose(q)
            ghost.show_visual = visible

    def show_planned_ghost(self, q: np.ndarray) -> None:
        """The blue ghost at `q`, a point of the planned path (Plan around plays it)."""
        if self._ghost_off:
            return  # another ghost took the view meanwhile
        self.ghosts.show("plan")
        self.ghost_shown = True
        for ok, ghost in self._ghosts.items():
            if ok:
                ghost.pose(q)
            ghost.show_visual = ok

    def plan_played(self) -> None:
        """The plan's playback is over: the ghost rests at the target, and the legend says so."""
        if self.ghost_shown is not None and not self._ghost_off:
            self.ghosts.show("target", blocked=not self.ghost_shown)

    def _at_target(self, q: np.ndarray | None) -> bool:
        here = self._current_q()
        return q is not None and here is not None and bool(np.allclose(here, q, atol=REACHED_TOL_RAD))

    @property
    def gizmo_shown(self) -> bool:
        return bool(self._gizmo.visible) and not self._gizmo_parked

    @property
    def gizmo_in_scene(self) -> bool:
        """The gizmo's node is visible (mounted in every page), at the TCP or parked while the arm moves."""
        return bool(self._gizmo.visible)

    @property
    def _gizmo_parked(self) -> bool:
        return bool(np.array_equal(self._gizmo.position, GIZMO_PARKED_M))

    @property
    def gizmo_position(self) -> np.ndarray:
        """Where the gizmo stands (base frame, metres): the target's TCP."""
        return np.asarray(self._gizmo.position, dtype=float)

    def _typed_texts(self) -> tuple[str, ...]:
        return tuple(field.text for field in self.joints)

    def _joint_q(self) -> np.ndarray:
        """The six typed angles (FieldInvalid naming each box that holds no usable number)."""
        return np.radians(read_all(self.joints))
