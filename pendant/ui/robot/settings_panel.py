"""Tool and base (zero point) forms: validated in the page before POST /tool or POST /base."""

from __future__ import annotations

import numpy as np
import viser
from pydantic import ValidationError

from pendant.cell.forms import position_from_form, vec3
from pendant.controller import Position, Tool
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.typed_field import NumberField, VectorField


class SettingsPanel:
    def __init__(self, target: GuiTarget, runner: CommandRunner) -> None:
        self._runner = runner
        with target.gui.add_folder("Tool (TCP offset from the flange)", expand_by_default=False):
            self.tool_name = target.gui.add_text("Name", initial_value="flange")
            self.tool_xyz = VectorField(
                target.gui, "XYZ mm", (0.0, 0.0, 0.0), hint="x, y, z", name="Tool XYZ mm"
            )
            self.tool_rpy = VectorField(
                target.gui, "RPY °", (0.0, 0.0, 0.0), hint="roll, pitch, yaw", name="Tool RPY °"
            )
            self.tool_radius = NumberField(target.gui, "Radius mm", 0.0, low=0.0, name="Tool radius mm")
            self.set_tool = target.gui.add_button("Set tool")
        with target.gui.add_folder("Base (zero point)", expand_by_default=False):
            self.base_xyz = VectorField(
                target.gui, "XYZ mm", (0.0, 0.0, 0.0), hint="x, y, z", name="Base XYZ mm"
            )
            self.base_rpy = VectorField(
                target.gui, "RPY °", (0.0, 0.0, 0.0), hint="roll, pitch, yaw", name="Base RPY °"
            )
            self.set_base = target.gui.add_button("Set base")
        self.set_tool.on_click(lambda e: self.submit_tool(e.client))
        self.set_base.on_click(lambda e: self.submit_base(e.client))

    def submit_tool(self, client: viser.ClientHandle | None) -> bool:
        try:
            position = position_from_form(vec3(self.tool_xyz.value), vec3(self.tool_rpy.value))
            name = self.tool_name.value.strip()
            if not name:
                raise ValueError("the tool needs a name")
            tool = Tool(
                name=name,
                point=position.point,
                rotation=position.rotation,
                radius=self.tool_radius.value / 1000.0,
            )
        except (ValueError, ValidationError) as error:
            _refuse(client, "Tool not set", error)
            return False
        self._runner.submit("Set tool", lambda c: c.set_tool(tool), client)
        return True

    def submit_base(self, client: viser.ClientHandle | None) -> bool:
        try:
            base = position_from_form(vec3(self.base_xyz.value), vec3(self.base_rpy.value))
        except (ValueError, ValidationError) as error:
            _refuse(client, "Base not set", error)
            return False
        self._runner.submit("Set base", lambda c: c.set_base(base), client)
        return True

    def show_current(self, tool: Tool, base: Position) -> None:
        self.tool_name.value = tool.name
        self.tool_xyz.show(np.array([tool.point.x, tool.point.y, tool.point.z]) * 1000.0)
        self.tool_rpy.show(np.degrees([tool.rotation.roll, tool.rotation.pitch, tool.rotation.yaw]))
        self.tool_radius.show(tool.radius * 1000.0)
        self.base_xyz.show(np.array([base.point.x, base.point.y, base.point.z]) * 1000.0)
        self.base_rpy.show(np.degrees([base.rotation.roll, base.rotation.pitch, base.rotation.yaw]))


def _refuse(client: viser.ClientHandle | None, title: str, error: Exception) -> None:
    message = error.errors()[0]["msg"] if isinstance(error, ValidationError) else str(error)
    if client is not None:
        client.add_notification(title=title, body=message, color="red", auto_close_seconds=8.0)
