"""The cell around the arm: the tool on the flange and the zero point (base) the positions are given in.

Frames. T_zero_tcp = inv(T_origbase_zero) @ fk(q) @ T_flange_tool, where
- T_origbase_zero is the zero point set by POST /base (its pose in the physical base frame), and
- T_flange_tool is the tool set by POST /tool, read as the pose of the new TCP relative to the flange (the
  original TCP). The reference calls the tool position the "distance from the arm's zero point to the new
  TCP"; every tool definition in practice (and the only reading under which a tool stays attached when the
  arm moves) is the offset from the flange, so that is what the simulator uses.
"""

from __future__ import annotations

import numpy as np

from pendant.controller.errors import PreconditionFailed
from pendant.controller.types import Point, Position, Rotation, Tool
from pendant.kinematics import ArmModel
from pendant.kinematics.transforms import inverse, matrix_to_position, position_to_matrix

DEFAULT_TOOL = Tool(
    name="flange",
    point=Point(x=0.0, y=0.0, z=0.0),
    rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0),
    radius=0.0,
)
DEFAULT_BASE = Position(point=Point(x=0.0, y=0.0, z=0.0), rotation=Rotation(roll=0.0, pitch=0.0, yaw=0.0))
# Offsets beyond these are typing errors, not tools or cells (and would overflow the frame arithmetic).
MAX_TOOL_OFFSET_M = 2.0
MAX_BASE_OFFSET_M = 100.0
MSG_TOOL_TOO_BIG = f"Tool offset and radius must be within {MAX_TOOL_OFFSET_M:g} m of the flange"
MSG_BASE_TOO_FAR = f"Zero point must be within {MAX_BASE_OFFSET_M:g} m of the arm base"


def check_tool_size(tool: Tool) -> None:
    offset = max(abs(tool.point.x), abs(tool.point.y), abs(tool.point.z))
    if offset > MAX_TOOL_OFFSET_M or tool.radius > MAX_TOOL_OFFSET_M:
        raise PreconditionFailed(MSG_TOOL_TOO_BIG)


def check_base_distance(base: Position) -> None:
    if max(abs(base.point.x), abs(base.point.y), abs(base.point.z)) > MAX_BASE_OFFSET_M:
        raise PreconditionFailed(MSG_BASE_TOO_FAR)


class Frames:
    """The tool and the zero point, with their matrices. Setting either makes new matrices, so identity of
    a matrix tells "not changed since" (what the planner's stale-plan check relies on)."""

    def __init__(self) -> None:
        self.apply_tool(DEFAULT_TOOL)
        self.apply_base(DEFAULT_BASE)

    def apply_tool(self, tool: Tool) -> None:
        self.tool = tool
        self.T_flange_tool = position_to_matrix(tool.position)

    def apply_base(self, base: Position) -> None:
        self.base = base
        self.T_origbase_zero = position_to_matrix(base)
        self.T_zero_origbase = inverse(self.T_origbase_zero)

    def position_of(self, arm: ArmModel, q: np.ndarray) -> Position:
        """The TCP position in the zero point frame for joint angles q."""
        return matrix_to_position(self.T_zero_origbase @ arm.fk(q) @ self.T_flange_tool)
