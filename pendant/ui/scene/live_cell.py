"""The controller's cell as the page knows it: its state, its geometry for the page's checks, and its
obstacles drawn in the shared scene (red where the arm touches one)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from pendant.cell.geometry import CellModel
from pendant.controller import Controller, Tool
from pendant.kinematics import ArmModel
from pendant.ui.kit.cell_contact import ContactLog, arm_contacts
from pendant.ui.kit.cell_state import CellState, read_cell_state
from pendant.ui.scene.cell import ObstacleDrawing


class LiveCell:
    def __init__(self, arm: ArmModel, drawing: ObstacleDrawing, contact_log: ContactLog) -> None:
        self.arm = arm
        self.drawing = drawing
        self.contact_log = (
            contact_log  # says in the event log when the arm touches an obstacle, and leaves it
        )
        self.state = CellState()
        self.model: CellModel | None = None  # None until the first read
        self._model_tool: Tool | None = None  # the tool the model was built with

    def update(self, controller: Controller, q: np.ndarray | None, tool: Tool | None) -> bool:
        """Read the cell and safety state; rebuild the geometry only when the obstacles, the tool's shape or
        the tool changed (True then); redraw the obstacles for the arm at `q`."""
        previous = self.state
        state = read_cell_state(controller, previous)
        changed = (
            self.model is None
            or state.obstacles != previous.obstacles
            or state.tool_shape != previous.tool_shape
            or tool is not self._model_tool
        )
        if changed:
            self._model_tool = tool
            self.model = CellModel(self.arm, state.obstacles, state.tool_shape, tool)
        touching = self.model.touching(q) if q is not None and self.model is not None else []
        if touching and q is not None and self.model is not None:  # depths and links only then
            state = replace(state, arm_contacts=arm_contacts(self.model.contacts(q)))
        self.state = state
        self.contact_log.note([o.name for o in state.obstacles], state.arm_contacts)
        self.drawing.show(state.obstacles, touching)
        return changed
