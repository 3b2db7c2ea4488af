"""The Program tab: the step list (record, add, reorder, nest, undo/redo), and the sections for the selected
step, the waypoint table, run control and the files (one module each).

One ProgramPanel per browser: it is a view of the shared ProgramWorkspace (the program, its file, the run)
and redraws when the workspace says something changed. What is selected is this browser's own: a line of
the step list (lines number the step tree depth first, as it is listed).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterator
from concurrent.futures import Future

import viser

from pendant.cell.geometry import CellModel
from pendant.controller import Controller
from pendant.kinematics import ArmModel
from pendant.program import Change, EditError, GripperAction, GripperStep, ProgramWorkspace
from pendant.program.tree import Line
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.program.check_section import CheckSection
from pendant.ui.program.file_section import FileSection
from pendant.ui.program.history_section import HistorySection
from pendant.ui.program.new_step import ADD_OPTIONS, STRUCTURE_OPTIONS, new_step, waypoint_here
from pendant.ui.program.refusals import USER_ERRORS
from pendant.ui.program.run_section import RunSection
from pendant.ui.program.scene import ProgramScene
from pendant.ui.program.step_form import StepForm
from pendant.ui.program.step_list import dropdown_lines, steps_markdown
from pendant.ui.program.waypoint_section import WaypointSection
from pendant.ui.scene.ghost_stage import GhostStage
from pendant.ui.scene.shared_urdf import SharedUrdf

log = logging.getLogger(__name__)

NO_STEP = "(no steps yet: press Record)"
NO_SELECTION = "(no step selected)"  # a new page selects nothing: Record and Add then append at the end
EDIT_OPTIONS = ("Up", "Down", "Indent", "Outdent", "Duplicate", "Delete step")


class ProgramPanel:
    """Build inside `with tabs.add_tab("Program", ...)`; `arm` (optional) draws the ghost and the 3D path."""

    def __init__(
        self,
        target: GuiTarget,
        shared: ProgramWorkspace,
        runner: CommandRunner,
        *,
        arm: ArmModel | None = None,
        current_cell: Callable[[], CellModel | None] = lambda: None,
        ghosts: GhostStage | None = None,
    ) -> None:
        self.target = target
        self.ghosts = ghosts if ghosts is not None else GhostStage()
        self.current_cell = current_cell  # Go to names what is in the way
        self.shared = shared
        self.commands = runner
        self.selected: int | None = None
        self.pending: Future[object] | None = None  # the last Record / Re-teach (tests wait on it)
        self.syncing = False  # set while redrawing: viser calls back for values we set
        gui = target.gui

        # --- the step list --------------------------------------------------------------------------
        self.title = gui.add_markdown("")
        self.steps_view = gui.add_markdown("")
        self.select = gui.add_dropdown("Step", options=[NO_STEP], initial_value=NO_STEP)
        self.record = gui.add_button(
            "Record", icon=viser.Icon.PLUS, hint="Add a move to a new waypoint where the arm is now"
        )
        self.insert_after = gui.add_checkbox(
            "Insert after selected step",
            initial_value=False,
            hint="Off: Record and Add put the new step at the end of the program",
        )
        self.add = gui.add_button_group("Add", options=ADD_OPTIONS)
        self.add_structure = gui.add_button_group("Add ", options=STRUCTURE_OPTIONS)
        self.order = gui.add_button_group("Edit", options=EDIT_OPTIONS)
        self.history = gui.add_button_group("History", options=("Undo", "Redo"))

        self.run_section = RunSection(self)
        self.check_section = CheckSection(self, arm)
        self.form = StepForm(self)
        self.waypoints = WaypointSection(self, arm)
        self.file_section = FileSection(self)
        self.history_section = HistorySection(self)
        self.scene = ProgramScene(target, arm)
        self._wire()
        self._listener = self._on_change
        shared.on_change(self._listener)
        self.redraw_program()
        self.file_section.redraw()
        self.run_section.redraw()

    # The run and file sections' controls, under the names the tab has always had.
    @property
    def run(self) -> viser.GuiButtonHandle:
        return self.run_section.run

    @property
    def progress(self) -> viser.GuiProgressBarHandle:  # type: ignore[name-defined]  # viser 1.1.1 does not export it
        return self.run_section.progress

    @property
    def run_status(self) -> viser.GuiMarkdownHandle:
        return self.run_section.status

    @property
    def locked(self) -> bool:
        return self.run_section.locked

    @locked.setter
    def locked(self, locked: bool) -> None:
        self.run_section.locked = locked
        self.run_section.redraw()

    def commanding_handles(self) -> Iterator[viser.GuiInputHandle]:
        """The controls only the operator may use (the session disables them, or hides button groups, for
        a viewer). Run and Step follow `locked`; the Yes/Cancel row shows only with a question."""
        yield from (self.record, self.add, self.add_structure, self.order, self.history)
        w = self.waypoints
        yield from (w.name, w.rename, w.reteach, w.go_to, w.teach_new, w.delete)
        yield from self.form.handles
        f = self.file_section
        yield from (
            self.run_section.loops.handle,
            f.file_name,
            f.files,
            f.upload,
            self.history_section.restore,
        )

    def close(self) -> None:
        """Stop following the workspace (the browser left)."""
        self.shared.remove_listener(self._listener)
        self.scene.close()
        self.history_section.close()
        self.check_section.close()

    # --- shared by the sections ----------------------------------------------------------------------
    def allowed(self, client: viser.ClientHandle | None, label: str) -> bool:
        return self.commands.refusal(client, label) is None

    def edit(self, label: str, client: viser.ClientHandle | None, action: Callable[[], object]) -> None:
        """A change to the shared program or files: refused for viewers; errors go to that browser."""
        if not self.allowed(client, label):
            return
        try:
            action()
        except USER_ERRORS as error:
            notify_refusal(client, f"{label} refused", str(error))
        else:
            self.commands.record(f"Program: {label}", client)

    def with_controller(
        self, label: str, client: viser.ClientHandle | None, action: Callable[[Controller], object]
    ) -> Future[object]:
        """An edit that reads the arm (Record, Re-teach): off the UI thread, like every controller call."""

        def guarded(controller: Controller) -> object:
            try:
                return action(controller)
            except USER_ERRORS as error:
                notify_refusal(client, f"{label} refused", str(error))
                return None

        self.pending = self.commands.submit(label, guarded, client)
        return self.pending

    def selected_line(self) -> Line | None:
        listed = self.shared.lines()
        if self.selected is None or not 0 <= self.selected < len(listed):
            return None
        return listed[self.selected]

    def select_line(self, index: int | None) -> None:
        self.selected = index
        self.redraw_program()

    def need_selection(self) -> int:
        if self.selected is None:
            raise EditError("Select a step first")
        return self.selected

    # --- wiring -------------------------------------------------------------------------------------
    def _wire(self) -> None:
        self.select.on_update(self._on_select)
        self.record.on_click(lambda e: self.with_controller("Record", e.client, self._record))
        self.add.on_click(lambda e: self.edit("Add step", e.client, lambda: self._add(str(self.add.value))))
        self.add_structure.on_click(
            lambda e: self.edit("Add step", e.client, lambda: self._add(str(self.add_structure.value)))
        )
        self.order.on_click(
            lambda e: self.edit(str(self.order.value), e.client, lambda: self._order(str(self.order.value)))
        )
        self.history.on_click(
            lambda e: self.edit(
                str(self.history.value), e.client, lambda: self._history(str(self.history.value))
            )
        )

    # --- editing (the step an Add button makes: new_step.py) -------------------------------------------
    def _insert_at(self) -> int | None:
        """Where a new step goes: after the selected line only when the operator asked so, else the end."""
        return self.selected if bool(self.insert_after.value) else None

    def _record(self, controller: Controller) -> None:
        self.select_line(self.shared.record_from(controller, after=self._insert_at()))

    def record_here(
        self, client: viser.ClientHandle | None, gripper: GripperAction | None = None
    ) -> Future[object]:
        """Record where the arm is and, with `gripper`, a gripper step after it (the Jog tab's teach row)."""
        label = "Record" if gripper is None else f"Record + {gripper.value.lower()} gripper"

        def record(controller: Controller) -> None:
            line = self.shared.record_from(controller, after=self._insert_at())
            if gripper is not None:
                line = self.shared.insert_step(GripperStep(action=gripper), after=line)
            self.select_line(line)

        return self.with_controller(label, client, record)

    def _add(self, option: str) -> None:
        line = self.selected_line()
        step = new_step(option, self.shared, waypoint_here(line, self.waypoints.chosen()))
        self.select_line(self.shared.insert_step(step, after=self._insert_at()))

    def _order(self, option: str) -> None:
        index = self.need_selection()
        match option:
            case "Up":
                self.select_line(self.shared.move_step(index, -1))
            case "Down":
                self.select_line(self.shared.move_step(index, +1))
            case "Indent":
                self.select_line(self.shared.indent(index))
            case "Outdent":
                self.select_line(self.shared.outdent(index))
            case "Duplicate":
                self.select_line(self.shared.duplicate_step(index))
            case "Delete step":
                self.shared.delete_step(index)
                count = len(self.shared.lines())
                self.select_line(min(index, count - 1) if count else None)

    def _history(self, option: str) -> None:
        if option == "Undo":
            self.shared.undo()
        else:
            self.shared.redo()

    # --- display ------------------------------------------------------------------------------------
    def _on_change(self, change: Change) -> None:
        if change is Change.PROGRAM:
            self.redraw_program()
        elif change is Change.FILES:
            self.file_section.redraw()
            self._redraw_title()
        elif change is Change.RUN:
            self.run_section.redraw()
            self._redraw_steps_view()

    def _on_select(self, event: viser.GuiEvent) -> None:
        if self.syncing or event.client is None:
            return  # viser also calls back (later, on its pool) for values we set: only a browser selects
        value = str(self.select.value)
        self.selected = int(value.split(".", 1)[0]) - 1 if value not in (NO_STEP, NO_SELECTION) else None
        self.redraw_program()

    def start_run(self, label: str, client: viser.ClientHandle | None) -> None:
        self.run_section.start(label, client)

    def run_allowed(self, label: str, client: viser.ClientHandle | None) -> bool:
        return self.check_section.allows(label, client)

    @property
    def ghost(self) -> SharedUrdf | None:
        return self.waypoints.ghost

    def redraw_program(self) -> None:
        listed = self.shared.lines()
        if self.selected is not None and not 0 <= self.selected < len(listed):
            self.selected = len(listed) - 1 if listed else None
        self.syncing = True
        try:
            lines = dropdown_lines(listed)
            # Nothing is selected until the operator picks a line (a reloaded page too): said, not guessed.
            options = [NO_SELECTION, *lines] if lines else [NO_STEP]
            if list(self.select.options) != options:
                self.select.options = options
            wanted = lines[self.selected] if self.selected is not None else options[0]
            if self.select.value != wanted:
                self.select.value = wanted
            line = self.selected_line()
            self.form.show(line.step if line is not None else None)
            self.waypoints.redraw(line.step if line is not None else None)
        finally:
            self.syncing = False
        self._redraw_steps_view()
        self._redraw_title()
        self.run_section.redraw()

    def _redraw_title(self) -> None:
        shared = self.shared
        where = f"`{shared.file_name}.json`" if shared.file_name else "not saved yet"
        state = " · unsaved changes (autosaved)" if shared.dirty else ""
        self.title.content = f"**{shared.program.name}** — {where}{state}"

    def _redraw_steps_view(self) -> None:
        listed, progress = self.shared.lines(), self.shared.progress
        self.steps_view.content = steps_markdown(listed, progress, self.selected, self.check_section.mark)
        self.scene.show(self.shared.program, self.selected, progress.step_index if progress.active else None)
