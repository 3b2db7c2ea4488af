"""The Program tab: record waypoints, edit the steps, run / step / pause / stop, and the program files.

One ProgramPanel per browser: it is a view of the shared ProgramWorkspace (the program, its file, the run)
and redraws when the workspace says something changed. What is selected is this browser's own.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from concurrent.futures import Future

import numpy as np
import viser
from viser.extras import ViserUrdf

from pendant.controller import Controller, MotionParams, MotionType, SignalLevel
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS, SPEED_MAX, SPEED_MIN
from pendant.kinematics import ArmModel
from pendant.program import (
    Change,
    EditError,
    GripperAction,
    GripperStep,
    MoveStep,
    OutputStep,
    ProgramFileError,
    ProgramWorkspace,
    RunnerBusy,
    RunState,
    Step,
    WaitInputStep,
    WaitStep,
    describe_step,
)
from pendant.program.models import DEFAULT_INPUT_TIMEOUT_MS, MAX_WAIT_MS
from pendant.ui.commands import CommandRunner, notify_refusal
from pendant.ui.gui_target import GuiTarget
from pendant.ui.program_scene import ProgramScene

log = logging.getLogger(__name__)

GHOST_RGBA = (0.2, 0.75, 0.35, 0.35)
NO_STEP = "(no steps yet: press Record)"
NO_FILE = "(no saved programs)"
ADD_OPTIONS = ("Gripper open", "Gripper close", "Set DO", "Wait DI", "Wait")
DEFAULT_WAIT_MS = 500
GO_TO_SPEED_PERCENT = 20.0
_USER_ERRORS = (EditError, ProgramFileError, RunnerBusy, OSError, ValueError)


class ProgramPanel:
    """Build inside `with tabs.add_tab("Program", ...)`; `arm` (optional) draws the ghost and the 3D path."""

    def __init__(
        self,
        target: GuiTarget,
        shared: ProgramWorkspace,
        runner: CommandRunner,
        *,
        arm: ArmModel | None = None,
    ) -> None:
        self._target = target
        self._shared = shared
        self._runner = runner
        self._arm = arm
        self._selected: int | None = None
        self._locked = False  # a viewer's panel: Run and Step stay disabled whatever the run state
        self.pending: Future[object] | None = None  # the last Record / Re-teach (tests wait on it)
        self._syncing = False
        gui = target.gui

        # --- the step list --------------------------------------------------------------------------
        self.title = gui.add_markdown("")
        self.steps_view = gui.add_markdown("")
        self.select = gui.add_dropdown("Step", options=[NO_STEP], initial_value=NO_STEP)
        self.record = gui.add_button(
            "Record", icon=viser.Icon.PLUS, hint="Add a move to where the arm is now"
        )
        self.add = gui.add_button_group("Add", options=ADD_OPTIONS)
        self.order = gui.add_button_group("Edit", options=("Up", "Down", "Duplicate", "Delete"))

        # --- running --------------------------------------------------------------------------------
        with gui.add_folder("Run"):
            self.loops = gui.add_number(
                "Loops", initial_value=1, min=0, max=100_000, step=1, hint="0: until Stop"
            )
            self.run = gui.add_button("Run", color="green", icon=viser.Icon.PLAYER_PLAY)
            self.step = gui.add_button("Step", icon=viser.Icon.PLAYER_TRACK_NEXT)
            self.pause = gui.add_button("Pause", icon=viser.Icon.PLAYER_PAUSE)
            self.stop = gui.add_button("Stop", color="red", icon=viser.Icon.PLAYER_STOP)
            self.progress = gui.add_progress_bar(0.0, animated=False)
            self.run_status = gui.add_markdown("Ready")

        # --- the selected step ----------------------------------------------------------------------
        with gui.add_folder("Selected step"):
            self.name = gui.add_text("Name", initial_value="")
            self.rename = gui.add_button("Rename", icon=viser.Icon.PENCIL)
            self.motion = gui.add_dropdown("Motion", options=[m.value for m in MotionType])
            self.speed = gui.add_slider("Speed %", min=SPEED_MIN, max=SPEED_MAX, step=1.0, initial_value=20.0)
            self.go_to = gui.add_button(
                "Go to", icon=viser.Icon.ARROW_RIGHT, hint="Move the arm to this waypoint"
            )
            self.reteach = gui.add_button(
                "Re-teach", icon=viser.Icon.REFRESH, hint="Overwrite with where the arm is"
            )
            self.preview = gui.add_checkbox("Preview (ghost)", initial_value=True)
            self.gripper = gui.add_dropdown("Gripper", options=[a.value for a in GripperAction])
            self.do_port = gui.add_dropdown("Output", options=[f"DO{p}" for p in OUTPUT_PORTS])
            self.di_port = gui.add_dropdown("Input", options=[f"DI{p}" for p in INPUT_PORTS])
            self.level = gui.add_dropdown("Level", options=[level.value for level in SignalLevel])
            self.timeout = gui.add_number("Timeout ms", initial_value=500, min=0, max=MAX_WAIT_MS, step=100)
            self.wait_ms = gui.add_number(
                "Wait ms", initial_value=DEFAULT_WAIT_MS, min=0, max=MAX_WAIT_MS, step=100
            )

        # --- files ----------------------------------------------------------------------------------
        with gui.add_folder("Files"):
            self.file_status = gui.add_markdown("")
            self.file_name = gui.add_text("Save as name", initial_value="")
            self.saved = gui.add_dropdown("Saved programs", options=[NO_FILE], initial_value=NO_FILE)
            self.files = gui.add_button_group("File", options=("New", "Save", "Save as", "Load", "Delete"))
            self.download = gui.add_button("Download .json", icon=viser.Icon.DOWNLOAD)
            self.export = gui.add_button("Export Python script", icon=viser.Icon.CODE)
            self.upload = gui.add_upload_button(
                "Upload .json", icon=viser.Icon.UPLOAD, mime_type="application/json"
            )

        self.scene = ProgramScene(target, arm)
        self._ghost = (
            ViserUrdf(target, arm.urdf_path, root_node_name="/program_ghost", mesh_color_override=GHOST_RGBA)
            if arm is not None and arm.urdf_path is not None
            else None
        )
        self._wire()
        self._listener = self._on_change
        shared.on_change(self._listener)
        self._redraw_program()
        self._redraw_files()
        self._redraw_run()

    @property
    def locked(self) -> bool:
        return self._locked

    @locked.setter
    def locked(self, locked: bool) -> None:
        self._locked = locked
        self._redraw_run()

    def close(self) -> None:
        """Stop following the workspace (the browser left)."""
        self._shared.remove_listener(self._listener)
        self.scene.close()

    # --- wiring -------------------------------------------------------------------------------------
    def _wire(self) -> None:
        self.select.on_update(self._on_select)
        self.record.on_click(lambda e: self._with_controller("Record", e.client, self._record))
        self.add.on_click(lambda e: self._edit("Add step", e.client, lambda: self._add(str(self.add.value))))
        self.order.on_click(
            lambda e: self._edit(str(self.order.value), e.client, lambda: self._order(str(self.order.value)))
        )
        self.rename.on_click(
            lambda e: self._edit("Rename", e.client, lambda: self._rename(str(self.name.value)))
        )
        for handle in (
            self.motion,
            self.speed,
            self.gripper,
            self.do_port,
            self.di_port,
            self.level,
            self.timeout,
            self.wait_ms,
        ):
            handle.on_update(self._on_field)
        self.preview.on_update(lambda _: self._show_ghost())
        self.go_to.on_click(lambda e: self._go_to(e.client))
        self.reteach.on_click(lambda e: self._with_controller("Re-teach", e.client, self._reteach))
        self.run.on_click(lambda e: self._start("Run", e.client))
        self.step.on_click(lambda e: self._start("Step", e.client))
        self.pause.on_click(
            lambda e: self._runner.submit("Pause", lambda _: self._shared.pause(), e.client, urgent=True)
        )
        # Stopping is always allowed (no gate) and runs on the urgent thread, like Freeze.
        self.stop.on_click(
            lambda e: self._runner.submit("Stop", lambda _: self._shared.stop(), e.client, urgent=True)
        )
        self.files.on_click(lambda e: self._file_action(str(self.files.value), e.client))
        self.download.on_click(lambda e: self._send(e.client, *self._shared.download()))
        self.export.on_click(lambda e: self._send(e.client, *self._shared.export()))
        self.upload.on_upload(self._on_upload)

    def _allowed(self, client: viser.ClientHandle | None, label: str) -> bool:
        return self._runner.refusal(client, label) is None

    def _edit(self, label: str, client: viser.ClientHandle | None, action: Callable[[], object]) -> None:
        """A change to the shared program or files: refused for viewers; errors go to that browser."""
        if not self._allowed(client, label):
            return
        try:
            action()
        except _USER_ERRORS as error:
            notify_refusal(client, f"{label} refused", str(error))
        else:
            self._runner.record(f"Program: {label}", client)

    def _with_controller(
        self, label: str, client: viser.ClientHandle | None, action: Callable[[Controller], object]
    ) -> Future[object]:
        """An edit that reads the arm (Record, Re-teach): off the UI thread, like every controller call."""

        def guarded(controller: Controller) -> object:
            try:
                return action(controller)
            except _USER_ERRORS as error:
                notify_refusal(client, f"{label} refused", str(error))
                return None

        self.pending = self._runner.submit(label, guarded, client)
        return self.pending

    # --- editing ------------------------------------------------------------------------------------
    def _record(self, controller: Controller) -> None:
        index = self._shared.record_from(controller, after=self._selected)
        self._select(index)

    def _rename(self, name: str) -> None:
        if self._selected is None:
            raise EditError("Select a step first")
        self._shared.rename(self._selected, name)

    def _reteach(self, controller: Controller) -> None:
        if self._selected is not None:
            self._shared.reteach_from(controller, self._selected)

    def _add(self, option: str) -> None:
        step: Step = {
            "Gripper open": GripperStep(action=GripperAction.OPEN),
            "Gripper close": GripperStep(action=GripperAction.CLOSE),
            "Set DO": OutputStep(port=OUTPUT_PORTS[0], level=SignalLevel.HIGH),
            "Wait DI": WaitInputStep(
                port=INPUT_PORTS[0], level=SignalLevel.HIGH, timeout_ms=DEFAULT_INPUT_TIMEOUT_MS
            ),
            "Wait": WaitStep(ms=DEFAULT_WAIT_MS),
        }[option]
        self._select(self._shared.insert_step(step, after=self._selected))

    def _order(self, option: str) -> None:
        index = self._selected
        if index is None:
            raise EditError("Select a step first")
        if option == "Up":
            self._select(self._shared.move_step(index, -1))
        elif option == "Down":
            self._select(self._shared.move_step(index, +1))
        elif option == "Duplicate":
            self._select(self._shared.duplicate_step(index))
        elif option == "Delete":
            self._shared.delete_step(index)
            count = len(self._shared.program.steps)
            self._select(min(index, count - 1) if count else None)

    def _on_field(self, event: viser.GuiEvent) -> None:
        if self._syncing or event.client is None or self._selected is None:
            return  # our own redraw, or nothing to edit
        index = self._selected
        self._edit("Edit step", event.client, lambda: self._apply_fields(index))

    def _apply_fields(self, index: int) -> None:
        program = self._shared.program
        if index >= len(program.steps):
            return
        step = program.steps[index]
        if isinstance(step, MoveStep):
            self._shared.set_motion(index, MotionType(self.motion.value), float(self.speed.value))
            return
        level = SignalLevel(self.level.value)
        timeout = int(self.timeout.value)
        updated: Step
        match step:
            case GripperStep():
                updated = GripperStep(action=GripperAction(self.gripper.value), timeout_ms=timeout)
            case OutputStep():
                updated = OutputStep(port=int(str(self.do_port.value)[2:]), level=level)
            case WaitInputStep():
                updated = WaitInputStep(
                    port=int(str(self.di_port.value)[2:]), level=level, timeout_ms=timeout
                )
            case WaitStep():
                updated = WaitStep(ms=int(self.wait_ms.value))
            case _:
                return
        self._shared.replace_step(index, updated)

    def _go_to(self, client: viser.ClientHandle | None) -> None:
        step = self._selected_step()
        if not isinstance(step, MoveStep):
            return
        params = MotionParams(speed=GO_TO_SPEED_PERCENT, motion_type=step.motion)
        label = f"Go to {step.waypoint.name}"
        if step.motion is MotionType.JOINT:
            self._runner.submit(label, lambda c: c.set_pose(step.waypoint.pose, params), client, motion=True)
        else:
            self._runner.submit(
                label, lambda c: c.set_position(step.waypoint.position, params), client, motion=True
            )

    # --- running ------------------------------------------------------------------------------------
    def _start(self, label: str, client: viser.ClientHandle | None) -> None:
        if not self._allowed(client, label):
            return
        progress = self._shared.progress
        try:
            if label == "Step":
                self._shared.start_step()
            elif progress.state is RunState.PAUSED:
                self._shared.start_resume()
            else:
                self._shared.start_run(loops=int(self.loops.value))
        except _USER_ERRORS as error:
            notify_refusal(client, f"{label} refused", str(error))
        else:
            self._runner.record(f"Program: {label} {self._shared.program.name!r}", client)

    # --- files --------------------------------------------------------------------------------------
    def _file_action(self, option: str, client: viser.ClientHandle | None) -> None:
        saved = str(self.saved.value)
        actions: dict[str, Callable[[], object]] = {
            "New": self._shared.new,
            "Save": self._shared.save,
            "Save as": lambda: self._shared.save_as(str(self.file_name.value)),
            "Load": lambda: self._shared.load(saved) if saved != NO_FILE else None,
            "Delete": lambda: self._shared.delete_file(saved) if saved != NO_FILE else None,
        }

        def act() -> None:
            actions[option]()
            if option in ("Save", "Save as") and client is not None:
                client.add_notification(
                    title="Saved",
                    body=f"{self._shared.file_name}.json",
                    color="green",
                    auto_close_seconds=3.0,
                )
            if option in ("New", "Load"):
                self._select(0 if self._shared.program.steps else None)

        self._edit(option, client, act)

    def _on_upload(self, event: viser.GuiEvent) -> None:
        uploaded = self.upload.value
        self._edit("Upload", event.client, lambda: self._shared.upload(uploaded.name, uploaded.content))

    def _send(self, client: viser.ClientHandle | None, filename: str, content: bytes) -> None:
        if client is not None:
            client.send_file_download(filename, content)

    # --- display ------------------------------------------------------------------------------------
    def _on_change(self, change: Change) -> None:
        if change is Change.PROGRAM:
            self._redraw_program()
        elif change is Change.FILES:
            self._redraw_files()
        elif change is Change.RUN:
            self._redraw_run()

    def _select(self, index: int | None) -> None:
        self._selected = index
        self._redraw_program()

    def _on_select(self, event: viser.GuiEvent) -> None:
        if self._syncing or event.client is None:
            return  # viser also calls back (later, on its pool) for values we set: only a browser selects
        value = str(self.select.value)
        self._selected = int(value.split(".", 1)[0]) - 1 if value != NO_STEP else None
        self._redraw_program()

    def _selected_step(self) -> Step | None:
        steps = self._shared.program.steps
        if self._selected is None or not 0 <= self._selected < len(steps):
            return None
        return steps[self._selected]

    def _redraw_program(self) -> None:
        program = self._shared.program
        steps = program.steps
        if self._selected is not None and not 0 <= self._selected < len(steps):
            self._selected = len(steps) - 1 if steps else None
        self._syncing = True
        try:
            options = [f"{i + 1}. {describe_step(s)}" for i, s in enumerate(steps)] or [NO_STEP]
            if list(self.select.options) != options:
                self.select.options = options
            wanted = options[self._selected] if self._selected is not None else options[0]
            if self.select.value != wanted:
                self.select.value = wanted
            if self._selected is None and steps:
                self._selected = 0
            self._show_fields(self._selected_step())
        finally:
            self._syncing = False
        self._redraw_steps_view()
        self._redraw_title()
        self._show_ghost()

    def _redraw_title(self) -> None:
        shared = self._shared
        where = f"`{shared.file_name}.json`" if shared.file_name else "not saved yet"
        state = " · unsaved changes (autosaved)" if shared.dirty else ""
        self.title.content = f"**{shared.program.name}** — {where}{state}"

    def _redraw_steps_view(self) -> None:
        progress = self._shared.progress
        current = progress.step_index if progress.active else None
        lines = []
        for i, step in enumerate(self._shared.program.steps):
            mark = (
                "✖"
                if i == progress.failed_step
                else "▶"
                if i == current
                else "●"
                if i == self._selected
                else ""
            )
            text = f"{mark} {i + 1}. {describe_step(step)}"
            lines.append(f"**{text}**" if mark else text)
        self.steps_view.content = "  \n".join(lines) if lines else "_No steps: jog the arm and press Record._"
        self.scene.show(self._shared.program, self._selected, current)

    def _show_fields(self, step: Step | None) -> None:
        kind = type(step)
        self.name.visible = self.rename.visible = self.motion.visible = self.speed.visible = kind is MoveStep
        self.go_to.visible = self.reteach.visible = self.preview.visible = kind is MoveStep
        self.gripper.visible = kind is GripperStep
        self.do_port.visible = kind is OutputStep
        self.di_port.visible = kind is WaitInputStep
        self.level.visible = kind in (OutputStep, WaitInputStep)
        self.timeout.visible = kind in (GripperStep, WaitInputStep)
        self.wait_ms.visible = kind is WaitStep
        match step:
            case MoveStep():
                self.name.value = step.waypoint.name
                self.motion.value = step.motion.value
                self.speed.value = step.speed
            case GripperStep():
                self.gripper.value = step.action.value
                self.timeout.value = step.timeout_ms
            case OutputStep():
                self.do_port.value = f"DO{step.port}"
                self.level.value = step.level.value
            case WaitInputStep():
                self.di_port.value = f"DI{step.port}"
                self.level.value = step.level.value
                self.timeout.value = step.timeout_ms
            case WaitStep():
                self.wait_ms.value = step.ms

    def _show_ghost(self) -> None:
        if self._ghost is None:
            return
        step = self._selected_step()
        visible = isinstance(step, MoveStep) and bool(self.preview.value)
        self._ghost.show_visual = visible
        if visible and isinstance(step, MoveStep):
            cfg = np.zeros(len(self._ghost.get_actuated_joint_names()))
            cfg[:6] = np.radians(step.waypoint.pose.angles)
            self._ghost.update_cfg(cfg)

    def _redraw_files(self) -> None:
        names = self._shared.saved_programs() or [NO_FILE]
        self._syncing = True
        try:
            if list(self.saved.options) != names:
                self.saved.options = names
            current = self._shared.file_name
            if current in names and self.saved.value != current:
                self.saved.value = current
            if not self.file_name.value and current:
                self.file_name.value = current
        finally:
            self._syncing = False
        folder = self._shared.store.folder
        status = f"Programs folder: `{folder}` ({len(self._shared.saved_programs())} saved)"
        problem = self._shared.store.restore_problem
        if problem is not None:  # said until the pendant restarts: the refused file waits in the folder
            status += f"  \n**{problem}**"
        self.file_status.content = status
        self._redraw_title()

    def _redraw_run(self) -> None:
        progress = self._shared.progress
        self.progress.value = round(100.0 * progress.progress, 1)
        color = {"failed": "red", "paused": "orange", "finished": "green"}.get(progress.state.value)
        self.progress.color = color
        text = progress.message
        self.run_status.content = f"**{text}**" if progress.state is RunState.FAILED else text
        self.run.label = "Resume" if progress.state is RunState.PAUSED else "Run"
        running = progress.state is RunState.RUNNING
        self.run.disabled = self.step.disabled = running or self._locked
        self.pause.disabled = not running
        self._redraw_steps_view()
