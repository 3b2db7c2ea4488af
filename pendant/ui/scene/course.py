"""A line through points in the scene: the course the TCP will take (a planned path), shown in one browser."""

from __future__ import annotations

import numpy as np
import viser

COURSE_RGB = (30, 110, 255)  # the blue of the executable ghost, opaque so the line reads against it
THICKNESS_PX = 4.0  # on screen: the course stays readable zoomed out


class CourseLine:
    """One polyline at `name` in `scene`; `show(points)` replaces it, `hide()` removes it from view."""

    def __init__(self, scene: viser.SceneApi, name: str, rgb: tuple[int, int, int] = COURSE_RGB) -> None:
        self._scene = scene
        self._name = name
        self._rgb = rgb
        self._handle: viser.LineSegmentsHandle | None = None

    def show(self, points: np.ndarray) -> None:
        """Draw the polyline through `points` (n, 3), metres in the base frame (n >= 2)."""
        segments = np.stack([points[:-1], points[1:]], axis=1).astype(np.float32)
        colors = np.broadcast_to(np.array(self._rgb, dtype=np.uint8), segments.shape).copy()
        if self._handle is None:
            self._handle = self._scene.add_line_segments(
                self._name, segments, colors, thickness=THICKNESS_PX, thickness_units="screen"
            )
        else:
            self._handle.points = segments
            self._handle.colors = colors
            self._handle.visible = True

    def hide(self) -> None:
        if self._handle is not None and self._handle.visible:
            self._handle.visible = False

    @property
    def shown(self) -> bool:
        return self._handle is not None and bool(self._handle.visible)
