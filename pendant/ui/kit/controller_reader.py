"""The refresh loop's reading of the controller: a snapshot each tick; with the IO, the tool too, and the
robot id until the controller has given one (it may have been down when the pendant started)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TypeVar

import numpy as np

from pendant.controller import Controller, ControllerError, Tool
from pendant.kinematics.transforms import position_to_matrix
from pendant.ui.kit.snapshot import Snapshot, read_snapshot

T = TypeVar("T")


def read_quietly(read: Callable[[], T], default: T) -> T:
    try:
        return read()
    except ControllerError:
        return default


class ControllerReader:
    def __init__(self, controller: Controller) -> None:
        self.controller = controller
        self.robot_id = read_quietly(controller.get_robot_id, "")
        self.tool: Tool | None = None  # the last tool read
        self.T_flange_tool = np.eye(4)  # its TCP on the flange: the scene's TCP frame and the gizmo

    def read(self, latest: Snapshot, *, with_io: bool) -> Snapshot:
        """A new snapshot; without `with_io` it keeps `latest`'s IO."""
        snapshot = read_snapshot(
            self.controller, with_io=with_io, robot_id=self.robot_id, tool_name=latest.tool_name
        )
        if not with_io:
            return replace(snapshot, outputs=latest.outputs, inputs=latest.inputs)
        if snapshot.online:  # an offline controller would only make each of these reads time out too
            tool = read_quietly(self.controller.get_tool, None)
            if tool is not None:
                self.T_flange_tool = position_to_matrix(tool.position)
                self.tool = tool
                snapshot = replace(snapshot, tool_name=tool.name)
            if not self.robot_id:  # the controller was unreachable when the pendant started
                self.robot_id = read_quietly(self.controller.get_robot_id, "")
                snapshot = replace(snapshot, robot_id=self.robot_id)
        return snapshot
