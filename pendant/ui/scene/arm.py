"""The 3D scene: floor, base and TCP frames, the arm from its URDF, kept in step with the controller."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import viser
import viser.transforms as vtf
from viser.extras import ViserUrdf

from pendant.config import EnvironmentMap
from pendant.kinematics.limits import GRIPPER_STROKE_M
from pendant.ui.scene.trail import TcpTrail

FLOOR_SIZE_M = 2.0
FRAME_AXES_LENGTH_M = 0.12
FRAME_AXES_RADIUS_M = 0.004
FILL_GROUND_RGB = (170, 170, 170)  # light from below: the floor's
FILL_INTENSITY = 1.5
# Three-quarter view from the front right, the arm filling the view.
CAMERA_POSITION_M = (0.9, -1.05, 0.75)
CAMERA_LOOK_AT_M = (-0.1, -0.05, 0.3)


class ArmScene:
    """The live arm: call `show(q, gripper_opening, T_base_tcp)` whenever the controller's state changes."""

    def __init__(
        self, server: viser.ViserServer, urdf_path: Path, environment_map: EnvironmentMap | None = None
    ) -> None:
        """`environment_map`: one of viser's HDR maps (pendant.config.ENVIRONMENT_MAPS) to light the view
        with; None: lights alone."""
        self._server = server
        server.scene.set_up_direction("+z")
        # Shadow maps double the rendering work; on a pendant without a GPU (software WebGL) that is the
        # difference between the arm keeping up with a jog and lagging behind it.
        server.scene.configure_default_lights(cast_shadow=False)
        if environment_map is None:
            # viser's default HDR map costs a page in software WebGL ~10 s of CPU at load (decoding it and
            # prefiltering it, on the first frame) and keeps its view at 5 % opacity for ~7 s meanwhile
            # (benchmarks/page_load.py). A sky-and-floor fill with viser's two directional lights gives the
            # white plastic arm nearly the same look for nothing.
            server.scene.configure_environment_map(None)
            server.scene.add_light_hemisphere(
                "/fill",
                sky_color=(255, 255, 255),
                ground_color=FILL_GROUND_RGB,
                intensity=FILL_INTENSITY,
                position=(0.0, 0.0, 1.0),  # the sky above: the fill's direction is its position
            )
        else:
            server.scene.configure_environment_map(environment_map)
        server.initial_camera.position = CAMERA_POSITION_M
        server.initial_camera.look_at = CAMERA_LOOK_AT_M
        server.scene.add_grid(
            "/floor",
            width=FLOOR_SIZE_M,
            height=FLOOR_SIZE_M,
            cell_size=0.1,
            section_size=0.5,
            plane_color=(245, 245, 245),
            plane_opacity=0.6,
        )
        server.scene.add_frame(
            "/base_frame", axes_length=FRAME_AXES_LENGTH_M * 1.5, axes_radius=FRAME_AXES_RADIUS_M
        )
        self._arm = ViserUrdf(server, urdf_path, root_node_name="/arm")
        self._n_actuated = len(self._arm.get_actuated_joint_names())
        self._tcp_frame = server.scene.add_frame(
            "/tcp_frame", axes_length=FRAME_AXES_LENGTH_M, axes_radius=FRAME_AXES_RADIUS_M
        )
        self.trail = TcpTrail(server)
        self._last: tuple[np.ndarray, float] | None = None

    @property
    def last_shown(self) -> tuple[np.ndarray, float] | None:
        """The joint angles and gripper opening last sent to the browsers (a new object on every change)."""
        return self._last

    def show(
        self, q: np.ndarray, gripper_opening: float, T_base_tcp: np.ndarray, now: float | None = None
    ) -> None:
        """Move the arm to joint angles q (radians) with the gripper `gripper_opening` (0 closed, 1 open);
        `now` (monotonic seconds) times the trail."""
        self.trail.update(time.monotonic() if now is None else now, T_base_tcp[:3, 3])
        if self._last is not None and np.array_equal(self._last[0], q) and self._last[1] == gripper_opening:
            return  # nothing changed: send nothing to the browsers
        self._last = (q.copy(), gripper_opening)
        cfg = np.zeros(self._n_actuated)
        cfg[:6] = q
        if self._n_actuated > 6:
            cfg[6:] = gripper_opening * GRIPPER_STROKE_M
        self._arm.update_cfg(cfg)
        self._tcp_frame.position = T_base_tcp[:3, 3]
        self._tcp_frame.wxyz = vtf.SO3.from_matrix(T_base_tcp[:3, :3]).wxyz
