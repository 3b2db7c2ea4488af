"""What a recording needs to draw the arm in Foxglove's 3D panel: each link's mesh with its visual origin
(read from the URDF with yourdfpy), and each link's pose for a joint vector (the pendant's own kinematics).

The meshes are read when a recording first draws the arm, not when the pendant starts: yourdfpy brings in
trimesh, scipy and networkx, 0.65 of the 1.5 CPU-s a `pendant --no-ui` (the simulator a user's CI starts)
took to answer, and most pendants never record (benchmarks/start_up.py)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from pendant.kinematics import ArmModel

LinkPoses = Callable[[np.ndarray], dict[str, np.ndarray]]


@dataclass(frozen=True)
class LinkMesh:
    link: str
    mesh: bytes  # glTF binary, as the URDF names it
    T_link_visual: np.ndarray


@dataclass(frozen=True)
class ArmDrawing:
    """The arm as a recording draws it: `link_poses(q)` gives T_base_link for every link (q in radians)."""

    urdf: Path
    link_poses: LinkPoses

    @cached_property
    def meshes(self) -> tuple[LinkMesh, ...]:
        return link_meshes(self.urdf)


def link_meshes(urdf_path: Path) -> tuple[LinkMesh, ...]:
    import yourdfpy

    robot = yourdfpy.URDF.load(str(urdf_path), load_meshes=False, build_scene_graph=False)
    meshes = []
    for link in robot.robot.links:
        for visual in link.visuals:
            mesh = visual.geometry.mesh if visual.geometry is not None else None
            if mesh is None:
                continue
            path = (urdf_path.parent / mesh.filename).resolve()
            if path.suffix.lower() != ".glb" or not path.is_file():
                continue  # only what Foxglove draws as it is (model/gltf-binary)
            origin = visual.origin if visual.origin is not None else np.eye(4)
            meshes.append(LinkMesh(link.name, path.read_bytes(), np.asarray(origin, dtype=float)))
    return tuple(meshes)


def arm_drawing(arm: ArmModel) -> ArmDrawing | None:
    """The arm's meshes from its URDF (None for an arm built without one) and its links' poses from the
    pendant's kinematics."""
    if arm.urdf_path is None:
        return None
    return ArmDrawing(urdf=arm.urdf_path, link_poses=arm.fk_all_links)
