"""A refused pose drawn in one browser: a red ghost of the arm there and, in red, the obstacles it would hit
(a Go to or a program step refused for a collision)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np

from pendant.controller.cell_types import Obstacle
from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.scene.cell import ObstacleDrawing
from pendant.ui.scene.shared_urdf import SharedUrdf

REFUSED_RGBA = (0.95, 0.15, 0.15, 0.45)  # the Target tab's red ghost


class RefusedPose:
    """Hidden until `show`; `shown_q` says where the red ghost stands (None: hidden)."""

    def __init__(self, target: GuiTarget, urdf_path: Path | None, root: str) -> None:
        # Drawn at the first refusal (shared_urdf.py): until then the browser has none of its meshes.
        self._ghost = (
            SharedUrdf(target, urdf_path, root_node_name=root, mesh_color_override=REFUSED_RGBA)
            if urdf_path is not None
            else None
        )
        self._hits = ObstacleDrawing(target.scene, f"{root}_hits", only_touching=True)
        self.shown_q: np.ndarray | None = None
        self.hits: tuple[str, ...] = ()

    def show(self, q: np.ndarray, obstacles: Sequence[Obstacle], touching: Sequence[str]) -> None:
        if self.shown_q is not None and np.array_equal(self.shown_q, q) and tuple(touching) == self.hits:
            return
        self.shown_q, self.hits = q.copy(), tuple(touching)
        self._hits.show(obstacles, touching)
        if self._ghost is not None:
            self._ghost.pose(q)
            self._ghost.show_visual = True

    def hide(self) -> None:
        if self.shown_q is None:
            return
        self.shown_q, self.hits = None, ()
        self._hits.show([], ())
        if self._ghost is not None:
            self._ghost.show_visual = False
