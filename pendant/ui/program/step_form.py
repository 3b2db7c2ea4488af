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
from pendant.ui.kit.typed_field import NumberField, TypedField, VectorField
from pendant.ui.program.arrival import ARRIVAL_OPTIONS, arrival_actions, arrival_option
from pendant.ui.program.host import ProgramHost

Field = viser.GuiInputHandle | TypedField  # a dropdown, a checkbox or a typed box


class StepForm:
    def __init__(self, host: ProgramHost) -> None:
        self._host = host
        gui = host.target.gui
        with gui.add_folder("Selected step"):
            # Moves
            self.goes_to = gui.add_dropdown("Goes to", options=["-"], hint="The waypoint this move goes to")
            self.motion = gui.add_dropdown("Motion", options=[m.value for m in MotionType])
            self.speed = NumberField(gui, "Speed %", 20.0, low=PROGRAM_SPEED_MIN, high=SPEED_MAX, decimals=1)
            self.relative = gui.add_checkbox("Relative move", initial_value=False)
            self.offset_mm = VectorField(gui, "Offset mm", (0.0, 0.0, 0.0), hint="x, y, z")
            self.offset_deg = VectorField(gui, "Turn deg", (0.0, 0.0, 0.0), hint="about x, y, z")
            self.frame = gui.add_dropdown("Offset frame", options=[f.value for f in Frame])
            self.blend = NumberField(gui, "Blend mm", 0.0, low=0.0, high=500.0)
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
            self.timeout = NumberField(
                gui, "Timeout ms", 500, low=0, high=MAX_WAIT_MS, decimals=0, integer=True
            )
            self.wait_ms = NumberField(gui, "Wait ms", 500, low=0, high=MAX_WAIT_MS, decimals=0, integer=True)
            self.comment = gui.add_text("Comment", initial_value="")
            # Structure
            self.loop_mode = gui.add_dropdown("Repeat", options=[m.value for m in LoopMode])
            self.times = NumberField(gui, "Times", 2, low=0, high=MAX_LOOP_TIMES, decimals=0, integer=True)
            self.call = gui.add_dropdown("Program", options=["-"])
            self.pallet_name = gui.add_text("Pallet name", initial_value="Pallet")
            self.corners = [gui.add_dropdown(f"Corner {k}", options=["-"]) for k in (1, 2, 3)]
            grid = {"low": 1, "high": MAX_GRID, "decimals": 0, "integer": True}
            self.rows = NumberField(gui, "Rows", 2, **grid)  # type: ignore[arg-type]  # the same bounds
            self.columns = NumberField(gui, "Columns", 2, **grid)  # type: ignore[arg-type]
            self.layers = NumberField(gui, "Layers", 1, **grid)  # type: ignore[arg-type]
            self.layer_height = NumberField(gui, "Layer height mm", 0.0, low=0.0)
            self.approach = NumberField(gui, "Approach mm", 50.0, low=0.0)
            # Recorded path (its speed % is the approach to its start)
            self.path_speed = NumberField(
                gui,
                "Path mm/s",
                100.0,
                low=1.0,
                high=PATH_SPEED_MAX_MM_S,
                hint="TCP speed along the recorded path (Speed %: the move to its start)",
            )
            self.path_tol = VectorField(
                gui,
                "Path tol mm, °",
                (1.0, 1.0),
                low=0.01,
                decimals=2,
                hint="Changing it simplifies the path again from its kept recording",
            )
        self._groups: dict[type, tuple[Field, ...]] = {
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
            if isinstance(handle, TypedField):
                handle.on_commit(self._on_field)  # typed: when committed (Enter, leaving the box)
            else:
                handle.on_update(self._on_field)

    @property
    def handles(self) -> list[viser.GuiInputHandle]:
        """The form's controls as viser's handles (a typed field's text box)."""
        return [f.handle if isinstance(f, TypedField) else f for f in self.fields]

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
                self.speed.show(step.speed)
                self.relative.value = step.offset is not None
                o = step.offset or Offset()
                self.offset_mm.show((o.x, o.y, o.z))
                self.offset_deg.show((o.rx, o.ry, o.rz))
                self.frame.value = o.frame.value
                self.blend.show(step.blend_mm)
                self.arrival.value = arrival_option(step.actions[0] if step.actions else None)
                self.planned.value = step.planned
            case GripperStep():
                self.gripper.value = step.action.value
                self.timeout.show(step.timeout_ms)
            case OutputStep():
                self.do_port.value = f"DO{step.port}"
                self.level.value = step.level.value
            case WaitInputStep():
                self.di_port.value = f"DI{step.port}"
                self.level.value = step.level.value
                self.timeout.show(step.timeout_ms)
            case WaitStep():
                self.wait_ms.show(step.ms)
            case CommentStep():
                self.comment.value = step.text
            case LoopStep():
                self.loop_mode.value = step.mode.value
                self.times.show(step.times)
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
                self.rows.show(step.rows)
                self.columns.show(step.columns)
                self.layers.show(step.layers)
                self.layer_height.show(step.layer_height_mm)
                self.approach.show(step.approach_mm)
                self.speed.show(step.speed)
            case PathStep():
                self.speed.show(step.speed)
                self.path_speed.show(step.velocity_mm_s)
                self.path_tol.show((step.tol_mm, step.tol_deg))

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
                    speed=self.speed.value,
                    offset=offset,
                    blend_mm=self.blend.value,
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
                    layer_height_mm=self.layer_height.value,
                    approach_mm=self.approach.value,
                    speed=self.speed.value,
                )
            case PathStep():  # validated; another tolerance simplifies the kept recording again
                tol_mm, tol_deg = self.path_tol.value
                if (tol_mm, tol_deg) != (step.tol_mm, step.tol_deg):
                    step = resimplified(step, self._host.shared.path_recordings, tol_mm, tol_deg)
                fields = {"speed": self.speed.value, "velocity_mm_s": self.path_speed.value}
                updated = PathStep.model_validate({**dict(step), **fields})
            case _:
                return
        self._host.shared.replace_step(index, updated)
