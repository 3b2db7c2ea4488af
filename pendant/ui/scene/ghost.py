"""A translucent ghost of the arm in one browser's 3D view (or the shared scene), posed by joint angles: it
shows where the arm was or would be, and moves nothing."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.scene.shared_urdf import SharedUrdf


class GhostArm:
    """`show(q)` poses and shows it (q in radians, the six joints; a gripper stays closed); `hide()`."""

    def __init__(
        self, target: GuiTarget, urdf_path: Path, name: str, rgba: tuple[float, float, float, float]
    ) -> None:
        self._urdf = SharedUrdf(target, urdf_path, root_node_name=name, mesh_color_override=rgba)
        self._urdf.show_visual = False
        self.q: np.ndarray | None = None  # where it stands while shown

    def show(self, q: np.ndarray) -> None:
        if self.q is not None and np.array_equal(self.q, q):
            return  # nothing changed: send nothing to the browser
        self._urdf.pose(q)
        if self.q is None:
            self._urdf.show_visual = True
        self.q = np.array(q, dtype=float)

    def hide(self) -> None:
        if self.q is not None:
            self._urdf.show_visual = False
            self.q = None
