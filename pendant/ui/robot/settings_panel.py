"""Tool and base (zero point) forms: validated in the page before POST /tool or POST /base."""

from __future__ import annotations

import numpy as np
import viser
from pydantic import ValidationError

from pendant.cell.forms import position_from_form
from pendant.controller import Position, Tool
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget


class SettingsPanel:
    def __init__(self, target: GuiTarget, runner: CommandRunner) -> None:
        self._runner = runner
        with target.gui.add_folder("Tool (TCP offset from the flange)", expand_by_default=False):
            self.tool_name = target.gui.add_text("Name", initial_value="flange")
            self.tool_xyz = target.gui.add_vector3("XYZ mm", initial_value=(0.0, 0.0, 0.0), step=0.1)
            self.tool_rpy = target.gui.add_vector3("RPY °", initial_value=(0.0, 0.0, 0.0), step=0.1)
            self.tool_radius = target.gui.add_number("Radius mm", initial_value=0.0, min=0.0, step=0.1)
            self.set_tool = target.gui.add_button("Set tool")
        with target.gui.add_folder("Base (zero point)", expand_by_default=False):
            self.base_xyz = target.gui.add_vector3("XYZ mm", initial_value=(0.0, 0.0, 0.0), step=0.1)
            self.base_rpy = target.gui.add_vector3("RPY °", initial_value=(0.0, 0.0, 0.0), step=0.1)
            self.set_base = target.gui.add_button("Set base")
        self.set_tool.on_click(lambda e: self.submit_tool(e.client))
        self.set_base.on_click(lambda e: self.submit_base(e.client))

    def submit_tool(self, client: viser.ClientHandle | None) -> bool:
        try:
            position = position_from_form(tuple(self.tool_xyz.value), tuple(self.tool_rpy.value))
            name = self.tool_name.value.strip()
            if not name:
                raise ValueError("the tool needs a name")
            tool = Tool(
                name=name,
                point=position.point,
                rotation=position.rotation,
                radius=float(self.tool_radius.value) / 1000.0,
            )
        except (ValueError, ValidationError) as error:
            _refuse(client, "Tool not set", error)
            return False
        self._runner.submit("Set tool", lambda c: c.set_tool(tool), client)
        return True

    def submit_base(self, client: viser.ClientHandle | None) -> bool:
        try:
            base = position_from_form(tuple(self.base_xyz.value), tuple(self.base_rpy.value))
        except (ValueError, ValidationError) as error:
            _refuse(client, "Base not set", error)
            return False
        self._runner.submit("Set base", lambda c: c.set_base(base), client)
        return True

    def show_current(self, tool: Tool, base: Position) -> None:
        self.tool_name.value = tool.name
        self.tool_xyz.value = tuple(np.array([tool.point.x, tool.point.y, tool.point.z]) * 1000.0)
        self.tool_rpy.value = tuple(np.degrees([tool.rotation.roll, tool.rotation.pitch, tool.rotation.yaw]))
        self.tool_radius.value = tool.radius * 1000.0
        self.base_xyz.value = tuple(np.array([base.point.x, base.point.y, base.point.z]) * 1000.0)
        self.base_rpy.value = tuple(np.degrees([base.rotation.roll, base.rotation.pitch, base.rotation.yaw]))


def _refuse(client: viser.ClientHandle | None, title: str, error: Exception) -> None:
    message = error.errors()[0]["msg"] if isinstance(error, ValidationError) else str(error)
    if client is not None:
        client.add_notification(title=title, body=message, color="red", auto_close_seconds=8.0)
