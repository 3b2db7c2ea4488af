"""Fit view (the Jog tab's last button): this browser's camera framing the arm, its tool and every obstacle of
the cell (scene/framing.py). A page that opens on a cell with obstacles is fitted at once, and again while
its view changes shape (a phone's sheet, a turned tablet) until the operator moves the camera themselves."""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np
import viser

from pendant.cell.geometry import CellModel
from pendant.kinematics import ArmModel
from pendant.ui.scene.arm import CAMERA_LOOK_AT_M, CAMERA_POSITION_M
from pendant.ui.scene.framing import arm_spheres, fit_camera, obstacle_spheres

log = logging.getLogger(__name__)

MOVED_TOL_M = 1e-3  # the camera this far from where it was put: the operator moved it
# Where viser's page has its camera before it takes the pendant's first view: its first reports say so.
# three.js's own start (its camera at (0, 0, 5), y up) comes too, in some loads after the fit was sent.
# And until the page has shown a fit, no report is the operator's (a start-up place not listed here).
VISER_START_M = (3.0, 3.0, 3.0)
THREE_JS_START_M = (-5.0, 0.0, 0.0)
VIEW_DIRECTION = np.subtract(CAMERA_POSITION_M, CAMERA_LOOK_AT_M)


class ViewFit:
    def __init__(
        self,
        client: viser.ClientHandle,
        arm: ArmModel,
        current_q: Callable[[], np.ndarray | None],
        current_tool: Callable[[], np.ndarray],
        current_cell: Callable[[], CellModel | None],
    ) -> None:
        self._client = client
        self._arm = arm
        self._current_q = current_q
        self._current_tool = current_tool
        self._current_cell = current_cell
        self.button = client.gui.add_button(
            "Fit view", icon=viser.Icon.FOCUS_2, hint="Frame the arm, the tool and the cell's obstacles"
        )
        self.button.on_click(lambda _: self.fit())
        # Where the camera was put (the page's first view, then each Fit) while it follows the view's shape:
        # a report from the page may still carry the place before the last (it crossed the new one).
        cell = current_cell()
        self._following: list[np.ndarray] | None = (
            [np.asarray(CAMERA_POSITION_M, dtype=float)] if cell is not None and cell.obstacles else None
        )
        self._size: tuple[int, int] | None = None
        # The page has shown a fit: before that its camera is still its own start-up's (viser's start,
        # three.js's, the pendant's first view, in an order that varies with the load), never the operator's.
        self._shown = False
        client.camera.on_update(self._camera_changed)
        if self._following is not None:
            self.fit()  # now if the page has said how big its view is; else at its first word of it

    def fit(self) -> bool:
        """Frame the work in this browser's view now; False when the view's camera is not known yet."""
        camera = self._client.camera
        try:
            fov = camera.fov
        except AssertionError:  # viser's: the page has not said how big its view is yet
            return False
        q = self._current_q()
        if camera.image_height <= 0:
            return False
        if q is None:
            return False
        cell = self._current_cell()
        spheres = arm_spheres(self._arm.dh_frames(q), (self._arm.fk(q) @ self._current_tool())[:3, 3])
        spheres += obstacle_spheres(cell.obstacles if cell is not None else [])
        position, look_at = fit_camera(spheres, VIEW_DIRECTION, fov, camera.aspect)
        self._size = (camera.image_width, camera.image_height)
        camera.position = position
        camera.look_at = look_at
        placed = self._following[-1:] if self._following is not None else []
        self._following = [*placed, np.asarray(position, dtype=float)]
        return True

    def _camera_changed(self, camera: viser.CameraHandle) -> None:
        placed = self._following
        if placed is None:
            return
        here = np.asarray(camera.position)

        def at(p: np.ndarray) -> bool:
            return float(np.linalg.norm(here - p)) <= MOVED_TOL_M

        starts = (VISER_START_M, THREE_JS_START_M, CAMERA_POSITION_M)
        earlier = [*placed[:-1], *(np.array(p) for p in starts)]
        self._shown = self._shown or at(placed[-1])
        if at(placed[-1]) and (camera.image_width, camera.image_height) == self._size:
            return  # where the last fit put it, in a view of the same shape
        if self._shown and not at(placed[-1]) and not any(at(p) for p in earlier):
            self._following = None  # the operator's own view from now on
            return
        # The view changed shape, or the page shows a view from before the last fit (its first view,
        # taken after the fit was sent): fit again.
        try:
            self.fit()
        except Exception:  # a view that cannot be fitted keeps the one it has
            log.exception("fitting the view failed")
