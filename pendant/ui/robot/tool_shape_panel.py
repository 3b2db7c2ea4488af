"""Robot tab: the tool's shape (`/tool/shape`), the capsules the controller checks for collisions."""

from __future__ import annotations

from concurrent.futures import Future

import viser

from pendant.cell.forms import text_from_tool_shape, tool_shape_from_text
from pendant.controller.cell_types import ToolShape
from pendant.ui.kit.availability import Availability
from pendant.ui.kit.cell_state import CellState
from pendant.ui.kit.commands import CommandRunner, notify_refusal
from pendant.ui.kit.gui_target import GuiTarget

HINT = "Capsules on the flange, ';' between them: 'radius: x y z -> x y z' in mm (e.g. 30: 0 0 0 -> 0 0 150)"


class ToolShapePanel:
    def __init__(self, target: GuiTarget, runner: CommandRunner) -> None:
        self._runner = runner
        self._shown: ToolShape | None = None
        with target.gui.add_folder("Tool shape (collision capsules)", expand_by_default=False):
            self.capsules = target.gui.add_text("Capsules mm", initial_value="", hint=HINT)
            self.set_shape = target.gui.add_button("Set tool shape")
            self.availability = Availability(target.gui, "Tool shape", (self.capsules, self.set_shape))
        self.set_shape.on_click(lambda e: self.submit(e.client))

    def set_locked(self, locked: bool) -> None:
        """A viewer's page, or a controller without /tool/shape: greyed out."""
        self.availability.set_locked(locked)

    def submit(self, client: viser.ClientHandle | None = None) -> Future[object] | None:
        try:
            shape = tool_shape_from_text(str(self.capsules.value))
        except ValueError as error:
            notify_refusal(client, "Tool shape not set", str(error))
            return None
        return self.availability.learn(
            self._runner.submit("Set tool shape", lambda c: c.set_tool_shape(shape), client)
        )

    def show(self, state: CellState) -> None:
        """The controller's shape, when it changes (not while the operator types: only on a change)."""
        self.availability.show(state.unsupported.get("tool shape"))
        if state.tool_shape != self._shown:
            self._shown = state.tool_shape
            self.capsules.value = text_from_tool_shape(state.tool_shape)
