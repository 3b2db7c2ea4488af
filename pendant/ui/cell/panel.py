"""The Cell tab: add, edit, rename and delete the controller's obstacles, place the selected one with a
transform gizmo in the 3D view, save and load cell files.

No edit surprises: "Update selected obstacle" changes only the obstacle chosen in the list (never adds one,
never replaces another by renaming onto its name); "Add obstacle" only adds (a name in use is refused,
since the controller would replace that obstacle); deleting one or all asks first.

Every change goes to the controller (`/environment`); the scene, this list and the selected obstacle's fields
show what it then reports, so the picture and the controller's collision checks never disagree.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import replace
from pathlib import Path

import numpy as np
import viser

from pendant.cell.forms import KINDS, ObstacleForm, form_from_obstacle, obstacle_from_form, vec3
from pendant.cell.placement import gizmo_pose, moved_form
from pendant.controller import Controller
from pendant.controller.cell_types import Obstacle
from pendant.ui.cell.edits import DEFAULT_FORMS, NEW, clear_cell, edit_refusal
from pendant.ui.cell.files_section import CellFilesSection
from pendant.ui.cell.gizmo import ObstacleGizmo
from pendant.ui.kit.cell_contact import contact_line
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.confirm import Confirmation
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.typed_field import NumberField, TypedField, VectorField


class CellPanel:
    def __init__(
        self, target: GuiTarget, runner: CommandRunner, folder: Path, state: Callable[[], CellState]
    ) -> None:
        self._runner = runner
        self._state = state
        self._names: tuple[str, ...] = ()
        self._syncing = False
        self._pending_select: str | None = None  # an added obstacle to select once the controller lists it
        self._unsupported: str | None = None
        self._committed: Obstacle | None = None  # the selected obstacle as the controller holds it
        self._resting = DEFAULT_FORMS["BOX"]  # the fields where the gizmo rests (before a drag)
        self.locked = False  # a viewer's page
        self.gizmo = ObstacleGizmo(target.scene, self._dragged, self._released)
        gui = target.gui
        self.note = gui.add_markdown("Obstacles the controller checks every motion against.")
        self.selected = gui.add_dropdown("Obstacle", options=[NEW], initial_value=NEW)
        self.kind = gui.add_dropdown("Kind", options=list(KINDS), initial_value="BOX")
        self.name = gui.add_text("Name", initial_value="box")
        # Typed "x, y, z" boxes, committed on Enter or leaving the box (kit/typed_field.py): one left empty
        # or with letters refuses Add / Update with the reason, never an old value used silently.
        self.at = VectorField(gui, "Position mm", (400.0, 0.0, 100.0), hint="x, y, z in the base frame")
        self.rpy = VectorField(gui, "Rotation °", (0.0, 0.0, 0.0), hint="roll, pitch, yaw")
        self.size = VectorField(gui, "Size mm", (200.0, 200.0, 200.0), hint="x, y, z")
        self.end = VectorField(gui, "End mm", (0.0, 0.0, 100.0), hint="x, y, z of the capsule's other end")
        self.radius = NumberField(gui, "Radius mm", 50.0, low=0.0)
        self.apply = gui.add_button(
            "Update selected obstacle",
            icon=viser.Icon.DEVICE_FLOPPY,
            hint="Apply the fields to the obstacle chosen above",
        )
        self.add = gui.add_button(
            "Add obstacle", icon=viser.Icon.CUBE_PLUS, hint="A new obstacle from the fields (a new name)"
        )
        self.delete = gui.add_button("Delete obstacle", icon=viser.Icon.TRASH)
        self.clear = gui.add_button("Delete all obstacles", color="red")
        self.confirmation = Confirmation(target)
        f = self.files_section = CellFilesSection(gui, runner, folder)
        # Its controls and commands, under the names the tab has always had.
        self.file_name, self.save, self.files, self.load = f.file_name, f.save, f.files, f.load
        self.save_file, self.load_file = f.save_file, f.load_file
        self._show_fields("BOX")

        self.selected.on_update(lambda _: None if self._syncing else self._pick(self.selected.value))
        self.kind.on_update(lambda _: None if self._syncing else self._new_kind(self.kind.value))
        self.apply.on_click(lambda e: self.submit(e.client))
        self.add.on_click(lambda e: self.submit(e.client, add=True))
        self.delete.on_click(lambda e: self.ask_remove(e.client))
        self.clear.on_click(lambda e: self.ask_clear(e.client))

    @property
    def controls(self) -> tuple[viser.GuiInputHandle, ...]:
        """The fields only the operator may use (the commands: see `set_locked`)."""
        typed = (self.at, self.rpy, self.size, self.end, self.radius)
        return (self.selected, self.kind, self.name, *(field.handle for field in typed))

    @property
    def commands(self) -> tuple[viser.GuiButtonHandle, ...]:
        return (self.apply, self.add, self.delete, self.clear, self.save, self.load)

    def set_locked(self, locked: bool) -> None:
        """A viewer's page, or a controller without /environment: the commands are greyed out."""
        self.locked = locked
        disabled = locked or self._unsupported is not None
        for handle in self.commands:
            # Update and Delete need an obstacle chosen: greyed out on "(new obstacle)", not a surprise.
            needs_one = handle in (self.apply, self.delete) and self.selected.value == NEW
            if handle.disabled != (disabled or needs_one):
                handle.disabled = disabled or needs_one
        self._place_gizmo()

    # --- the form -----------------------------------------------------------------------------------
    def form(self) -> ObstacleForm:
        return ObstacleForm(
            kind=str(self.kind.value),
            name=str(self.name.value),
            at_mm=vec3(self.at.value),
            rpy_deg=vec3(self.rpy.value),
            size_mm=vec3(self.size.value),
            end_mm=vec3(self.end.value),
            radius_mm=float(self.radius.value),
        )

    def fill(self, form: ObstacleForm, *, resend: bool = False) -> None:
        """Show `form` in the fields; `resend`: even those the pendant believes the browser shows already
        (an edit the browser never sent leaves it showing another value: see `_resend`)."""
        self._syncing = True
        try:
            self.kind.value = form.kind
            self.name.value = form.name
            for field, value in (
                (self.at, form.at_mm),
                (self.rpy, form.rpy_deg),
                (self.size, form.size_mm),
                (self.end, form.end_mm),
            ):
                field.show(value, resend=resend)
            self.radius.show(form.radius_mm, resend=resend)
        finally:
            self._syncing = False
        self._show_fields(form.kind)

    def _show_fields(self, kind: str) -> None:
        """Only the fields that kind uses."""
        used = {"BOX": (self.rpy, self.size), "CAPSULE": (self.end, self.radius), "PLANE": (self.rpy,)}[kind]
        fields: tuple[TypedField, ...] = (self.rpy, self.size, self.end, self.radius)
        for handle in fields:
            visible = handle in used
            if handle.visible != visible:
                handle.visible = visible

    def _pick(self, name: str) -> None:
        obstacle = self._find(name)
        self._committed = obstacle
        self.set_locked(self.locked)  # Update and Delete follow the choice
        if obstacle is not None:
            self._load(obstacle)
        elif name == NEW:
            self.fill(DEFAULT_FORMS[str(self.kind.value)])
            self._place_gizmo()

    def _load(self, obstacle: Obstacle, *, resend: bool = False) -> None:
        """The selected obstacle as the controller holds it: in the fields and under the gizmo."""
        form = form_from_obstacle(obstacle)
        self.fill(form, resend=resend)
        self._resting = form
        self._place_gizmo()

    # --- the gizmo ----------------------------------------------------------------------------------
    def _place_gizmo(self) -> None:
        """On the selected obstacle, for the operator of a controller that has /environment; else hidden."""
        shown = self._committed is not None and not self.locked and self._unsupported is None
        self.gizmo.place(gizmo_pose(self._resting) if shown else None)

    def _dragged(self, T_from: np.ndarray, T_to: np.ndarray) -> None:
        """The gizmo moved: the fields follow (the controller hears of it on release)."""
        self.fill(replace(moved_form(self._resting, T_from, T_to), name=str(self.name.value)))

    def _released(self, T_from: np.ndarray, T_to: np.ndarray, client: viser.ClientHandle | None) -> None:
        """Send the placed obstacle; refused (it would touch the arm: 412), the gizmo and the fields go
        back to where the controller keeps it, and the notification says why."""
        self._resting = moved_form(self._resting, T_from, T_to)
        future = self.submit(client)
        if future is None:
            self._snap_back()
            return
        future.add_done_callback(lambda f: self._snap_back() if f.exception() is not None else None)

    def _snap_back(self) -> None:
        committed = self._committed
        if committed is not None:
            self._load(committed, resend=True)

    def _new_kind(self, kind: str) -> None:
        self._show_fields(kind)
        if self.selected.value == NEW:
            self.fill(DEFAULT_FORMS[kind])

    def _find(self, name: str) -> Obstacle | None:
        return next((o for o in self._state().obstacles if o.name == name), None)

    # --- commands -----------------------------------------------------------------------------------
    def submit(self, client: viser.ClientHandle | None = None, *, add: bool = False) -> Future[object] | None:
        """Update the selected obstacle from the fields (renaming it when the name changed); `add`: add a
        new one instead. Refused, with the reason, when it would add or replace something unasked."""
        try:
            obstacle = obstacle_from_form(self.form())
        except ValueError as error:
            notify_refusal(client, "Obstacle not added" if add else "Obstacle not updated", str(error))
            return None
        old = None if add else str(self.selected.value)
        refusal = edit_refusal({o.name for o in self._state().obstacles}, old, obstacle.name)
        if refusal is not None:
            notify_refusal(client, *refusal)
            return None

        def change(c: Controller) -> object:
            c.add_obstacle(obstacle)  # by name: an update replaces it
            if old is not None and old != obstacle.name:
                c.remove_obstacle(old)
            return obstacle.name

        verb = "Add" if add else "Update"
        future = self._runner.submit(f"{verb} obstacle {obstacle.name!r}", change, client)
        future.add_done_callback(lambda f: self._select_when_done(f, obstacle.name))
        return future

    def ask_remove(self, client: viser.ClientHandle | None = None) -> None:
        name = self.selected.value
        if name == NEW:
            notify_refusal(client, "Nothing deleted", "pick an obstacle first")
            return
        self.confirmation.ask(f"Delete the obstacle {name!r}?", self.remove)

    def ask_clear(self, client: viser.ClientHandle | None = None) -> None:
        count = len(self._state().obstacles)
        question = f"Delete all {count} obstacles? (A saved cell file brings them back.)"
        self.confirmation.ask(
            question, lambda answered_by: self._runner.submit("Delete all obstacles", clear_cell, answered_by)
        )

    def remove(self, client: viser.ClientHandle | None = None) -> Future[object] | None:
        name = self.selected.value
        if name == NEW:
            notify_refusal(client, "Nothing deleted", "pick an obstacle first")
            return None
        return self._runner.submit(f"Delete obstacle {name!r}", lambda c: c.remove_obstacle(name), client)

    def _select_when_done(self, future: Future[object], name: str) -> None:
        if future.exception() is None:
            self._pending_select = name

    # --- what the controller reports ----------------------------------------------------------------
    def show(self, state: CellState) -> None:
        names = tuple(o.name for o in state.obstacles)
        if names != self._names:
            self._names = names
            self._syncing = True
            try:
                self.selected.options = [NEW, *names]
                pending = self._pending_select
                if pending is not None and pending in names:
                    self.selected.value = pending
                    self._pending_select = None
                elif self.selected.value not in (NEW, *names):
                    self.selected.value = NEW
            finally:
                self._syncing = False
            self.set_locked(self.locked)  # Update and Delete follow what is chosen
        selected = self.selected.value
        obstacle = next((o for o in state.obstacles if o.name == selected), None)
        if obstacle is not None and obstacle != self._committed and not self.gizmo.dragging:
            # Added, updated, placed or changed by a script: the fields show what the controller applied
            # (even an edit the browser never sent shows up, rather than a value the controller never had).
            self._committed = obstacle
            self._load(obstacle, resend=True)
        elif obstacle is None and self._committed is not None:  # deleted
            self._committed = None
            self._place_gizmo()
        unsupported = state.unsupported.get("environment")
        text = (
            f"**Cell unavailable:** {unsupported}"
            if unsupported
            else f"{len(names)} obstacle(s); the controller checks every motion against them."
        )
        touching = contact_line(state.arm_contacts)
        if touching and not unsupported:
            text = f"{text}\n\n{touching}"
        if self.note.content != text:
            self.note.content = text
        if unsupported != self._unsupported:
            self._unsupported = unsupported
            self.set_locked(self.locked)
