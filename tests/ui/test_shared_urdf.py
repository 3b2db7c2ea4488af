"""Every browser's panels draw ghosts of the arm from one parse of its URDF (issue 37), not one parse each:
under 100 browsers coming and going the parses were among the panel builds' largest costs. A real page on
loopback; two browsers' panels built on the server's GUI."""

from __future__ import annotations

import asyncio
from typing import Any

import numpy as np
import pytest
import viser
import viser.transforms as tf
import yourdfpy
import zstandard

from pendant.kinematics.arm_model import ArmModel
from pendant.paths import urdf_path
from pendant.sim import SimController
from pendant.ui.scene import shared_urdf
from tests.support.headless_viewer import next_messages, open_viewer
from tests.support.pages import headless_session, pendant_page
from tests.support.ports import free_port
from tests.support.waiting import SAFETY_NET_S

RGBA = (0.9, 0.3, 0.2, 0.5)


def test_two_browsers_panels_parse_the_urdf_at_most_once(
    sim: SimController, monkeypatch: pytest.MonkeyPatch
) -> None:
    with pendant_page(sim, sim.arm) as page:
        shared_urdf.parsed.cache_clear()
        loads: list[Any] = []
        load = yourdfpy.URDF.load

        def counting(*args: Any, **kwargs: Any) -> Any:
            loads.append(args[0] if args else kwargs)
            return load(*args, **kwargs)

        monkeypatch.setattr(yourdfpy.URDF, "load", counting)
        headless_session(page)
        second = headless_session(page)  # on the same (server's) GUI: its ghosts replace the first's
        second.target_panel.set_joint_target(np.radians([-30.0, -60.0, 60.0, -90.0, -90.0, 0.0]))
        assert len(loads) <= 1, f"the URDF was parsed {len(loads)} times for two browsers"


Q_A = np.radians([30.0, -60.0, 60.0, -90.0, -90.0, 0.0])
Q_B = np.radians([-45.0, -30.0, 90.0, 0.0, 45.0, 20.0])
QUIET_S = 1.0  # no frame for this long: the replay of what the server holds has all come


def _local(props: dict[str, Any]) -> np.ndarray:
    T = np.eye(4)
    if "wxyz" in props:
        T[:3, :3] = tf.SO3(np.asarray(props["wxyz"], dtype=float)).as_matrix()
    if "position" in props:
        T[:3, 3] = props["position"]
    return T


async def _scene_as_seen(port: int) -> dict[str, np.ndarray]:
    """Each scene node's pose in its parent, as a browser that opens the page now ends up drawing it."""
    ws = await open_viewer(port)
    zstd = zstandard.ZstdDecompressor()
    poses: dict[str, dict[str, Any]] = {}
    try:
        async with asyncio.timeout(SAFETY_NET_S):
            while True:
                try:
                    messages = await asyncio.wait_for(next_messages(ws, zstd), QUIET_S)
                except TimeoutError:
                    break
                for message in messages:
                    name = message.get("name")
                    if not isinstance(name, str):
                        continue
                    props = message.get("props") if message["type"] == "FrameMessage" else message
                    pose = poses.setdefault(name, {})
                    pose.update({k: v for k, v in (props or {}).items() if k in ("wxyz", "position")})
    finally:
        await ws.close()
    return {name: _local(pose) for name, pose in poses.items()}


def _tcp_in_root(scene: dict[str, np.ndarray], root: str) -> np.ndarray:
    """The TCP's position under `root`, composed from the browser's frames along its path."""
    paths = [name for name in scene if name.startswith(root + "/") and name.endswith("/tcp")]
    assert len(paths) == 1, f"the browser got no single TCP frame under {root}: {paths}"
    path = paths[0]
    T = np.eye(4)
    parts = path.split("/")
    for depth in range(2, len(parts) + 1):
        T = T @ scene.get("/".join(parts[:depth]), np.eye(4))
    return T[:3, 3]


def test_a_ghost_first_shown_stands_where_it_was_posed() -> None:
    """Ghosts share one parse, and one that is drawn late (at its first show) must stand at the pose it was
    last given, whatever another ghost was posed at meanwhile: ViserUrdf adds its joint frames at the zero
    pose, and the replay's ghost, first shown at a step, stood there until its next different pose."""
    port = free_port()
    server = viser.ViserServer(host="127.0.0.1", port=port, verbose=False)
    try:
        path = urdf_path("pulse75")
        a = shared_urdf.SharedUrdf(server, path, root_node_name="/ghost_a", mesh_color_override=RGBA)
        b = shared_urdf.SharedUrdf(server, path, root_node_name="/ghost_b", mesh_color_override=RGBA)
        a.pose(Q_A)
        b.pose(Q_B)
        a.show_visual = True  # drawn now, at Q_A
        b.show_visual = True  # drawn after a, whose posing left the shared model at Q_A
        scene = asyncio.run(_scene_as_seen(port))
    finally:
        server.stop()
    arm = ArmModel.load("pulse75")
    for root, q in (("/ghost_a", Q_A), ("/ghost_b", Q_B)):
        expected = arm.fk_all_links(q)["tcp"][:3, 3]
        seen = _tcp_in_root(scene, root)
        assert np.linalg.norm(seen - expected) < 1e-6, f"{root}'s TCP is drawn at {seen}, posed at {expected}"
