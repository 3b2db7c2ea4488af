"""The selected obstacle's transform gizmo, in one browser's scene: a drag moves the Cell tab's fields (a few
times a second), the release sends the change to the controller once."""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np
import viser
import viser.transforms as vtf

GIZMO_SCALE = 0.25
FIELD_REFRESH_S = 0.1  # the fields follow a drag at most 10 times a second; the controller hears the release

Moved = Callable[[np.ndarray, np.ndarray], None]  # (T_base_gizmo where it rested, where it is now)
Released = Callable[[np.ndarray, np.ndarray, viser.ClientHandle | None], None]


class ObstacleGizmo:
    def __init__(
        self,
        scene: viser.SceneApi,
        on_move: Moved,
        on_release: Released,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self._on_move = on_move
        self._on_release = on_release
        self._clock = clock
        self.handle = scene.add_transform_controls("/cell_gizmo", scale=GIZMO_SCALE, visible=False)
        self.resting = np.eye(4)  # where the gizmo was put (the obstacle's pose in the fields)
        self.dragging = False
        self._shown_at = -math.inf
        self.handle.on_update(self._update)

    @property
    def pose(self) -> np.ndarray:
        """T_base_gizmo as the browser last reported it."""
        return vtf.SE3.from_rotation_and_translation(
            vtf.SO3(np.asarray(self.handle.wxyz)), np.asarray(self.handle.position)
        ).as_matrix()

    def place(self, T_base_gizmo: np.ndarray | None) -> None:
        """Put the gizmo at a pose (an obstacle is selected), or hide it (None)."""
        if T_base_gizmo is None:
            if self.handle.visible:
                self.handle.visible = False
            return
        self.resting = T_base_gizmo.copy()
        self.handle.position = T_base_gizmo[:3, 3]
        self.handle.wxyz = vtf.SO3.from_matrix(T_base_gizmo[:3, :3]).wxyz
        if not self.handle.visible:
            self.handle.visible = True

    async def _update(self, event: viser.TransformControlsEvent) -> None:
        # async: viser runs it on its event loop in the order the browser sent the phases (a thread pool
        # could run the release before the last move). Nothing here waits.
        if not self.handle.visible:
            return
        if event.phase == "start":
            self.dragging = True
            return
        now = self._clock()
        if event.phase == "update" and now - self._shown_at >= FIELD_REFRESH_S:
            self._shown_at = now
            self._on_move(self.resting, self.pose)
        elif event.phase == "end":
            self.dragging = False
            self._shown_at = -math.inf
            start, end = self.resting, self.pose
            self.resting = end
            self._on_move(start, end)
            self._on_release(start, end, event.client)
