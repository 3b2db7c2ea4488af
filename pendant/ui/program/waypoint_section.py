"""The Program tab's "Waypoints" folder: the waypoint table. Many moves may go to one waypoint: Re-teach moves
all of them, Rename keeps them pointing at it; Go to drives the arm there; a ghost arm previews it, only while
a move step is selected or the operator picked a waypoint (no ghost of something nobody asked to see)."""

from __future__ import annotations

import math

import numpy as np
import viser

from pendant.cell.collision_names import explain_collision
from pendant.controller import Controller, MotionParams, MotionType
from pendant.controller.errors import Collision, ControllerError
from pendant.kinematics import ArmModel
from pendant.program import EditError, MoveStep, Step, Waypoint
from pendant.ui.program.host import ProgramHost
from pendant.ui.scene.refused import RefusedPose
from pendant.ui.scene.shared_urdf import SharedUrdf

GHOST_RGBA = (0.2, 0.75, 0.35, 0.35)
GO_TO_SPEED_PERCENT = 20.0
NO_WAYPOINT = "(no waypoints yet)"


class WaypointSection:
    def __init__(self, host: ProgramHost, arm: ArmModel | None) -> None:
        self._host = host
        gui = host.target.gui
        with gui.add_folder("Waypoints"):
            self.table = gui.add_markdown("")
            self.chooser = gui.add_dropdown("Waypoint", options=[NO_WAYPOINT], initial_value=NO_WAYPOINT)
            self.name = gui.add_text("Name", initial_value="")
            self.rename = gui.add_button("Rename", icon=viser.Icon.PENCIL, hint="Every step using it follows")
            self.reteach = gui.add_button(
                "Re-teach", icon=viser.Icon.REFRESH, hint="Overwrite with where the arm is: every move to it"
            )
            self.go_to = gui.add_button("Go to", icon=viser.Icon.ARROW_RIGHT, hint="Move the arm to it")
            self.teach_new = gui.add_button(
                "Add waypoint here",
                icon=viser.Icon.MAP_PIN,
                hint="Teach a waypoint without a move (pallet corners)",
            )
            self.delete = gui.add_button(
                "Delete waypoint", icon=viser.Icon.TRASH, hint="Only when no step uses it"
            )
            self.preview = gui.add_checkbox("Preview (ghost)", initial_value=True)
        self._picked = False  # the operator chose a waypoint in the table (or taught one) to look at
        self._selected: Step | None = None  # the step the last redraw showed the waypoint of
        self._off = False  # another ghost took the view (ghost_stage.py): back when the operator picks again
        host.ghosts.register("waypoint", self._hide_ghost)
        self._ghost = (
            SharedUrdf(
                host.target, arm.urdf_path, root_node_name="/program_ghost", mesh_color_override=GHOST_RGBA
            )
            if arm is not None and arm.urdf_path is not None
            else None
        )
        self._arm = arm
        # A Go to refused for a collision: a red ghost there, the obstacle in red (cleared by the next one).
        self.refused = RefusedPose(
            host.target, arm.urdf_path if arm is not None else None, "/program_refused"
        )
        self.chooser.on_update(self._on_choose)
        self.rename.on_click(lambda e: host.edit("Rename", e.client, self._rename))
        self.reteach.on_click(
            lambda e: host.with_controller("Re-teach", e.client, lambda c: self.reteach_here(c, e.client))
        )
        self.teach_new.on_click(lambda e: host.with_controller("Add waypoint", e.client, self._teach_new))
        self.delete.on_click(lambda e: host.edit("Delete waypoint", e.client, self._delete))
        self.go_to.on_click(lambda e: self._go_to(e.client))
        self.preview.on_update(lambda _: self._preview_toggled())

    def chosen(self) -> str | None:
        value = str(self.chooser.value)
        return value if value in self._host.shared.program.waypoint_names() else None

    def _waypoint(self) -> Waypoint:
        name = self.chosen()
        if name is None:
            raise EditError("Choose a waypoint first")
        return self._host.shared.program.waypoint(name)

    def _on_choose(self, event: viser.GuiEvent) -> None:
        if self._host.syncing or event.client is None:
            return
        self._picked = True
        self._off = False
        self._show(self.chosen())

    # --- actions ------------------------------------------------------------------------------------
    def _rename(self) -> None:
        self._host.shared.rename_waypoint(self._waypoint().name, str(self.name.value))

    def reteach_here(self, controller: Controller, client: viser.ClientHandle | None = None) -> float:
        """The chosen waypoint where the arm is; it stays chosen, and the page says how far it moved (mm)."""
        old = self._waypoint()
        pose, position = controller.get_pose(), controller.get_position()
        self._host.shared.reteach_waypoint(old.name, pose, position)
        a, b = old.position.point, position.point
        moved_mm = 1000.0 * math.dist((a.x, a.y, a.z), (b.x, b.y, b.z))
        self._picked = True
        self._off = False
        self._show(old.name)
        if client is not None:
            client.add_notification(
                title=f"{old.name} re-taught",
                body=f"moved {moved_mm:.0f} mm",
                color="green",
                auto_close_seconds=6.0,
            )
        return moved_mm

    def _teach_new(self, controller: Controller) -> None:
        name = self._host.shared.add_waypoint(controller.get_pose(), controller.get_position())
        self._picked = True
        self._off = False
        self._show(name)

    def _delete(self) -> None:
        self._host.shared.delete_waypoint(self._waypoint().name)

    def _go_to(self, client: viser.ClientHandle | None) -> None:
        try:
            waypoint = self._waypoint()
        except EditError:
            return
        line = self._host.selected_line()
        motion = (
            line.step.motion if line is not None and isinstance(line.step, MoveStep) else MotionType.JOINT
        )
        params = MotionParams(speed=GO_TO_SPEED_PERCENT, motion_type=motion)
        label = f"Go to {waypoint.name}"
        q = np.radians(np.asarray(waypoint.pose.angles, dtype=float))

        def go(c: Controller) -> None:
            self.refused.hide()
            try:
                if motion is MotionType.JOINT:
                    c.set_pose(waypoint.pose, params)
                else:
                    c.set_position(waypoint.position, params)
            except Collision as error:
                raise self._named(error, q, c) from error

        self._host.commands.submit(label, go, client, motion=True)

    def _named(self, error: Collision, q: np.ndarray, controller: Controller) -> Collision:
        """The refusal with what is in the way named (cell/collision_names.py), and the red ghost shown."""
        if self._arm is None:
            return error
        cell = self._host.current_cell()
        try:
            here: np.ndarray | None = np.radians(np.asarray(controller.get_pose().angles, dtype=float))
        except ControllerError:
            here = None
        named = explain_collision(error.message, self._arm, q, cell, here)
        self.refused.show(q, cell.obstacles if cell is not None else [], named.obstacles)
        return Collision(named.reason)

    # --- display ------------------------------------------------------------------------------------
    def redraw(self, selected: Step | None) -> None:
        """The table, and the waypoint of the selected move chosen (called while the host is syncing)."""
        program = self._host.shared.program
        rows = [f"{w.name} ({program.uses_of(w.name)} uses)" for w in program.waypoints]
        self.table.content = "  \n".join(rows) if rows else "_No waypoints: jog the arm and press Record._"
        names = program.waypoint_names() or [NO_WAYPOINT]
        if list(self.chooser.options) != names:
            self.chooser.options = names
        chose = selected != self._selected  # another step chosen (not a redraw after an edit elsewhere)
        self._selected = selected
        if selected is not None and chose:
            self._picked = False  # a step chosen: its move (if any) is what the ghost shows
            self._off = False
        if isinstance(selected, MoveStep) and (chose or not self._picked):
            self._show(selected.waypoint)
        elif self.chooser.value not in names:
            self._show(names[0])
        else:
            self._show(str(self.chooser.value))

    def _show(self, name: str | None) -> None:
        if name is not None and self.chooser.value != name:
            self.chooser.value = name
        if name is not None and name in self._host.shared.program.waypoint_names():
            self.name.value = name
        self._show_ghost()

    @property
    def ghost(self) -> SharedUrdf | None:
        """The tab's translucent ghost arm (the Check's playback moves it too)."""
        return self._ghost

    def _preview_toggled(self) -> None:
        self._off = False
        self._show_ghost()

    def _hide_ghost(self) -> None:
        """Another ghost took the view (the stage calls this)."""
        self._off = True
        if self._ghost is not None:
            self._ghost.show_visual = False

    def _show_ghost(self) -> None:
        if self._ghost is None:
            return
        name = self.chosen()
        selected = self._host.selected_line()
        asked = self._picked or (selected is not None and isinstance(selected.step, MoveStep))
        visible = name is not None and bool(self.preview.value) and asked and not self._off
        if visible:
            self._host.ghosts.show("waypoint")
        else:  # the Check's playback moves this same ghost: hidden, it is gone too
            self._host.ghosts.hidden("waypoint")
            self._host.ghosts.hidden("check")
        if visible and name is not None:  # posed first: a ghost drawn at its first show stands there
            self._ghost.pose(np.radians(self._host.shared.program.waypoint(name).pose.angles))
        self._ghost.show_visual = visible
