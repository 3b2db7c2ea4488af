"""The Program tab's "Selected step" folder: the fields of the selected step, one set per kind, applied as
one edit whenever the operator changes one of them."""

from __future__ import annotations

import viser

from pendant.controller import MotionType, SignalLevel
from pendant.controller.types import INPUT_PORTS, OUTPUT_PORTS, SPEED_MAX
from pendant.program import (
    CallStep,
    CommentStep,
    Frame,
    GripperAction,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    Offset,
    OutputStep,
    PalletStep,
    PathStep,
    Step,
    WaitInputStep,
    WaitStep,
)
from pendant.program.limits import (
    MAX_GRID,
    MAX_LOOP_TIMES,
    MAX_WAIT_MS,
    PATH_SPEED_MAX_MM_S,
    PROGRAM_SPEED_MIN,
)
from pendant.teach.path_step import resimplified
from pendant.ui.program.arrival import ARRIVAL_OPTIONS, arrival_actions, arrival_option
from pendant.ui.program.host import ProgramHost


class StepForm:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        gui = host.target.gui
        with gui.add_folder("Selected step"):
            # Moves
            self.goes_to = gui.add_dropdown("Goes to", options=["-"], hint="The waypoint this move goes to")
            self.motion = gui.add_dropdown("Motion", options=[m.value for m in MotionType])
            self.speed = gui.add_slider(
                "Speed %", min=PROGRAM_SPEED_MIN, max=SPEED_MAX, step=1.0, initial_value=20.0
            )
            self.relative = gui.add_checkbox("Relative move", initial_value=False)
            self.offset_mm = gui.add_vector3("Offset mm", initial_value=(0.0, 0.0, 0.0), step=1.0)
            self.offset_deg = gui.add_vector3("Turn deg", initial_value=(0.0, 0.0, 0.0), step=1.0)
            self.frame = gui.add_dropdown("Offset frame", options=[f.value for f in Frame])
            self.blend = gui.add_number("Blend mm", initial_value=0.0, min=0.0, max=500.0, step=1.0)
            self.arrival = gui.add_dropdown("At arrival", options=list(ARRIVAL_OPTIONS))
            self.planned = gui.add_checkbox(
                "Plan around obstacles",
                initial_value=False,
                hint="Move J only: the path around the cell's obstacles is found each time the step runs",
            )
            # Single steps
            self.gripper = gui.add_dropdown("Gripper", options=[a.value for a in GripperAction])
            self.do_port = gui.add_dropdown("Output", options=[f"DO{p}" for p in OUTPUT_PORTS])
            self.di_port = gui.add_dropdown("Input", options=[f"DI{p}" for p in INPUT_PORTS])
            self.level = gui.add_dropdown("Level", options=[level.value for level in SignalLevel])
            self.timeout = gui.add_number("Timeout ms", initial_value=500, min=0, max=MAX_WAIT_MS, step=100)
            self.wait_ms = gui.add_number("Wait ms", initial_value=500, min=0, max=MAX_WAIT_MS, step=100)
            self.comment = gui.add_text("Comment", initial_value="")
            # Structure
            self.loop_mode = gui.add_dropdown("Repeat", options=[m.value for m in LoopMode])
            self.times = gui.add_number("Times", initial_value=2, min=0, max=MAX_LOOP_TIMES, step=1)
            self.call = gui.add_dropdown("Program", options=["-"])
            self.pallet_name = gui.add_text("Pallet name", initial_value="Pallet")
            self.corners = [gui.add_dropdown(f"Corner {k}", options=["-"]) for k in (1, 2, 3)]
            self.rows = gui.add_number("Rows", initial_value=2, min=1, max=MAX_GRID, step=1)
            self.columns = gui.add_number("Columns", initial_value=2, min=1, max=MAX_GRID, step=1)
            self.layers = gui.add_number("Layers", initial_value=1, min=1, max=MAX_GRID, step=1)
            self.layer_height = gui.add_number("Layer height mm", initial_value=0.0, min=0.0, step=1.0)
            self.approach = gui.add_number("Approach mm", initial_value=50.0, min=0.0, step=1.0)
            # Recorded path (its speed % is the approach to its start)
            self.path_speed = gui.add_number(
                "Path mm/s",
                initial_value=100.0,
                min=1.0,
                max=PATH_SPEED_MAX_MM_S,
                step=10.0,
                hint="TCP speed along the recorded path (Speed %: the move to its start)",
            )
            self.path_tol = gui.add_vector2(
                "Path tol mm, °",
                initial_value=(1.0, 1.0),
                min=(0.01, 0.01),
                step=0.1,
                hint="Changing it simplifies the path again from its kept recording",
            )
        self._groups: dict[type, tuple[viser.GuiInputHandle, ...]] = {
            MoveStep: (
                self.goes_to,
                self.motion,
                self.speed,
                self.relative,
                self.offset_mm,
                self.offset_deg,
                self.frame,
                self.blend,
                self.arrival,
                self.planned,
            ),
            GripperStep: (self.gripper, self.timeout),
            OutputStep: (self.do_port, self.level),
            WaitInputStep: (self.di_port, self.level, self.timeout),
            WaitStep: (self.wait_ms,),
            CommentStep: (self.comment,),
            LoopStep: (self.loop_mode, self.times, self.di_port, self.level),
            IfStep: (self.di_port, self.level),
            CallStep: (self.call,),
            PalletStep: (
                self.pallet_name,
                *self.corners,
                self.rows,
                self.columns,
                self.layers,
                self.layer_height,
                self.approach,
                self.speed,
            ),
            PathStep: (self.speed, self.path_speed, self.path_tol),
        }
        # Handles are not hashable: unique by identity, in form order.
        self.fields = list({id(h): h for group in self._groups.values() for h in group}.values())
        for handle in self.fields:
            handle.on_update(self._on_field)

    def _on_field(self, event: viser.GuiEvent) -> None:
        host = self._host
        if host.syncing or event.client is None or host.selected is None:
            return  # our own redraw, or nothing to edit
        index = host.selected
        host.edit("Edit step", event.client, lambda: self._apply(index))

    # --- showing ------------------------------------------------------------------------------------
    def show(self, step: Step | None) -> None:
        """Show the fields of `step`'s kind, filled in (called while the host is syncing)."""
        shown = {id(h) for h in self._groups.get(type(step), ())}
        for handle in self.fields:
            handle.visible = id(handle) in shown
        if isinstance(step, MoveStep):
            offset = step.offset
            # Which fields a relative move uses: shown only for one.
            for handle in (self.offset_mm, self.offset_deg, self.frame):
                handle.visible = offset is not None
            self.planned.visible = step.motion is MotionType.JOINT  # a Move L goes straight
        names = self._host.shared.program.waypoint_names() or ["-"]
        for dropdown in (self.goes_to, *self.corners):
            if list(dropdown.options) != names:
                dropdown.options = names
        match step:
            case MoveStep():
                self.goes_to.value = step.waypoint
                self.motion.value = step.motion.value
                self.speed.value = step.speed
                self.relative.value = step.offset is not None
                o = step.offset or Offset()
                self.offset_mm.value = (o.x, o.y, o.z)
                self.offset_deg.value = (o.rx, o.ry, o.rz)
                self.frame.value = o.frame.value
                self.blend.value = step.blend_mm
                self.arrival.value = arrival_option(step.actions[0] if step.actions else None)
                self.planned.value = step.planned
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
            case CommentStep():
                self.comment.value = step.text
            case LoopStep():
                self.loop_mode.value = step.mode.value
                self.times.value = step.times
                self.times.visible = step.mode is LoopMode.TIMES
                self.di_port.visible = self.level.visible = step.mode is not LoopMode.TIMES
                self.di_port.value = f"DI{step.port}"
                self.level.value = step.level.value
            case IfStep():
                self.di_port.value = f"DI{step.port}"
                self.level.value = step.level.value
            case CallStep():
                saved = self._host.shared.saved_programs()
                options = saved if step.program in saved else [step.program, *saved]
                if list(self.call.options) != options:
                    self.call.options = options
                self.call.value = step.program
            case PalletStep():
                self.pallet_name.value = step.name
                for dropdown, corner in zip(self.corners, step.corners, strict=True):
                    dropdown.value = corner
                self.rows.value, self.columns.value, self.layers.value = step.rows, step.columns, step.layers
                self.layer_height.value = step.layer_height_mm
                self.approach.value = step.approach_mm
                self.speed.value = step.speed
            case PathStep():
                self.speed.value = step.speed
                self.path_speed.value = step.velocity_mm_s
                self.path_tol.value = (step.tol_mm, step.tol_deg)

    # --- applying -----------------------------------------------------------------------------------
    def _apply(self, index: int) -> None:
        listed = self._host.shared.lines()
        if index >= len(listed):
            return
        step = listed[index].step
        level = SignalLevel(self.level.value)
        updated: Step
        match step:
            case MoveStep():
                offset = None
                if self.relative.value:
                    (x, y, z), (rx, ry, rz) = self.offset_mm.value, self.offset_deg.value
                    offset = Offset(x=x, y=y, z=z, rx=rx, ry=ry, rz=rz, frame=Frame(self.frame.value))
                updated = MoveStep(
                    waypoint=str(self.goes_to.value),
                    motion=MotionType(self.motion.value),
                    speed=float(self.speed.value),
                    offset=offset,
                    blend_mm=float(self.blend.value),
                    actions=arrival_actions(str(self.arrival.value)),
                    planned=bool(self.planned.value) and self.motion.value == MotionType.JOINT.value,
                )
            case GripperStep():
                updated = GripperStep(
                    action=GripperAction(self.gripper.value), timeout_ms=int(self.timeout.value)
                )
            case OutputStep():
                updated = OutputStep(port=int(str(self.do_port.value)[2:]), level=level)
            case WaitInputStep():
                port = int(str(self.di_port.value)[2:])
                updated = WaitInputStep(port=port, level=level, timeout_ms=int(self.timeout.value))
            case WaitStep():
                updated = WaitStep(ms=int(self.wait_ms.value))
            case CommentStep():
                updated = CommentStep(text=str(self.comment.value))
            case LoopStep():
                updated = LoopStep(
                    mode=LoopMode(self.loop_mode.value),
                    times=int(self.times.value),
                    port=int(str(self.di_port.value)[2:]),
                    level=level,
                )
            case IfStep():
                updated = IfStep(port=int(str(self.di_port.value)[2:]), level=level)
            case CallStep():
                updated = CallStep(program=str(self.call.value))
            case PalletStep():
                first, last_in_row, last_in_column = (str(c.value) for c in self.corners)
                updated = PalletStep(
                    name=str(self.pallet_name.value),
                    corners=(first, last_in_row, last_in_column),
                    rows=int(self.rows.value),
                    columns=int(self.columns.value),
                    layers=int(self.layers.value),
                    layer_height_mm=float(self.layer_height.value),
                    approach_mm=float(self.approach.value),
                    speed=float(self.speed.value),
                )
            case PathStep():  # validated; another tolerance simplifies the kept recording again
                tol_mm, tol_deg = (float(v) for v in self.path_tol.value)
                if (tol_mm, tol_deg) != (step.tol_mm, step.tol_deg):
                    step = resimplified(step, self._host.shared.path_recordings, tol_mm, tol_deg)
                fields = {"speed": float(self.speed.value), "velocity_mm_s": float(self.path_speed.value)}
                updated = PathStep.model_validate({**dict(step), **fields})
            case _:
                return
        self._host.shared.replace_step(index, updated)
