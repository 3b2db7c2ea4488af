"""The arm's URDF parsed once for every browser's ghosts (issue 37), not once per ghost.

Each browser's panels draw four ghosts of the arm (the Target tab's two, the Program tab's, the banner's
refused pose) and viser's ViserUrdf parsed the URDF and its meshes for each: a profile of 100 browsers coming
and going found a yourdfpy parse among the panel builds' largest costs. One parse is shared here. yourdfpy's
model keeps the last configuration it was posed in, so a ghost's posing (and its building, which reads the
model's transforms) take turns under one lock; they only queue messages for the browsers, quickly.
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


class SharedUrdf(ViserUrdf):
    """A ViserUrdf drawn from the shared parse of `urdf_path`."""

    def __init__(
        self,
        target: GuiTarget,
        urdf_path: Path,
        *,
        root_node_name: str,
        mesh_color_override: tuple[float, float, float, float],
    ) -> None:
        model = parsed(Path(urdf_path))
        with _posing:
            super().__init__(
                target, model, root_node_name=root_node_name, mesh_color_override=mesh_color_override
            )

    def update_cfg(self, configuration: np.ndarray) -> None:
        with _posing:
            super().update_cfg(configuration)
