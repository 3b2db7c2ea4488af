"""The arm's URDF parsed once for every browser's ghosts (issue 37), not once per ghost, and a ghost's meshes
sent to its browser only when it is first shown.

Each browser's panels draw four ghosts of the arm (the Target tab's two, the Program tab's, the banner's
refused pose) and viser's ViserUrdf parsed the URDF and its meshes for each: a profile of 100 browsers coming
and going found a yourdfpy parse among the panel builds' largest costs. One parse is shared here. yourdfpy's
model keeps the last configuration it was posed in, so a ghost's posing (and its drawing, which reads the
model's transforms) take turns under one lock; they only queue messages for the browsers, quickly.

A ghost is drawn (its frames and meshes sent) the first time it is shown: most pages never show the
Target tab's red ghost or the Program tab's preview, and the three eager ghosts were some 250 of the ~640
messages of a newcomer's panels and most of its bytes (the arm's meshes, three times over), in the pendant
and again in the browser, which parsed them into the 3D view's scene while the page loaded.
"""

from __future__ import annotations

import functools
import threading
from pathlib import Path
from typing import Any

import numpy as np
import yourdfpy
from viser.extras import ViserUrdf

from pendant.ui.kit.gui_target import GuiTarget

ARM_JOINTS = 6  # the arm's joints come first among the actuated ones, the gripper's after

_posing = threading.Lock()


@functools.cache
def parsed(urdf_path: Path) -> Any:
    """The URDF and its meshes as ViserUrdf loads them from a path, once a path."""
    return yourdfpy.URDF.load(
        urdf_path,
        build_scene_graph=True,
        build_collision_scene_graph=False,
        load_meshes=True,
        load_collision_meshes=False,
        filename_handler=functools.partial(yourdfpy.filename_handler_magic, dir=urdf_path.parent),
    )


class SharedUrdf:
    """A ghost of the arm drawn from the shared parse of `urdf_path` under `root_node_name`: hidden (and
    not yet in the browser's scene) until `show_visual` is first set; `update_cfg` poses it, drawn or not
    (a ghost not drawn yet is drawn at the last pose it was given)."""

    def __init__(
        self,
        target: GuiTarget,
        urdf_path: Path,
        *,
        root_node_name: str,
        mesh_color_override: tuple[float, float, float, float],
    ) -> None:
        self._target = target
        self._model = parsed(Path(urdf_path))
        self._root_node_name = root_node_name
        self._rgba = mesh_color_override
        self._drawn: ViserUrdf | None = None
        self._cfg: np.ndarray | None = None  # the pose given before it was drawn

    @property
    def show_visual(self) -> bool:
        drawn = self._drawn
        return drawn is not None and drawn.show_visual

    @show_visual.setter
    def show_visual(self, visible: bool) -> None:
        drawn = self._drawn
        if drawn is None and not visible:
            return  # never drawn: nothing to hide, nothing to send
        if drawn is None:
            drawn = self._draw()
        drawn.show_visual = visible

    def update_cfg(self, configuration: np.ndarray) -> None:
        with _posing:
            if self._drawn is None:
                self._cfg = np.array(configuration, dtype=float)
            else:
                self._drawn.update_cfg(configuration)

    def pose(self, q: np.ndarray) -> None:
        """Poses the arm's six joints at `q` (radians); any other actuated joint (the gripper) stays at 0."""
        configuration = np.zeros(len(self._model.actuated_joint_names))
        configuration[:ARM_JOINTS] = q[:ARM_JOINTS]
        self.update_cfg(configuration)

    def get_actuated_joint_names(self) -> tuple[str, ...]:
        return tuple(self._model.actuated_joint_names)

    def remove(self) -> None:
        if self._drawn is not None:
            self._drawn.remove()

    def _draw(self) -> ViserUrdf:
        with _posing:
            if self._drawn is None:  # another thread may have drawn it meanwhile
                self._drawn = ViserUrdf(
                    self._target,
                    self._model,
                    root_node_name=self._root_node_name,
                    mesh_color_override=self._rgba,
                )
                if self._cfg is not None:  # ViserUrdf adds its joint frames unposed (at 0) until posed
                    self._drawn.update_cfg(self._cfg)
            return self._drawn
