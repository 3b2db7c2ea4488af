"""Fit view's camera (pendant/ui/scene/framing.py): every sphere of the work projects inside the view, for a
wide desk view, an upright tablet's narrow one and a phone's, with the pendant's usual viewing direction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.kinematics import ArmModel
from pendant.ui.page.view_fit import VIEW_DIRECTION
from pendant.ui.scene.framing import arm_spheres, fit_camera, obstacle_spheres

FOV_RAD = math.radians(50.0)
HOME_DEG = (0.0, -90.0, 90.0, -90.0, -90.0, 0.0)


def in_view(
    position: np.ndarray, look_at: np.ndarray, point: np.ndarray, radius: float, aspect: float
) -> bool:
    """The sphere wholly inside a pinhole camera's view (z up, vertical field FOV_RAD)."""
    forward = (look_at - position) / np.linalg.norm(look_at - position)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    d = point - position
    depth = float(d @ forward)
    tan_v = math.tan(FOV_RAD / 2)
    tan_h = tan_v * aspect
    # The sphere's edge, pushed out sideways and up by its radius (a slightly generous bound).
    return (
        depth > radius
        and abs(float(d @ right)) + radius <= depth * tan_h
        and abs(float(d @ up)) + radius <= depth * tan_v
    )


@pytest.mark.parametrize("aspect", [1012 / 900, 380 / 1024, 390 / 282])
def test_the_arm_its_tool_and_a_box_far_to_one_side_are_all_in_view(aspect: float) -> None:
    arm = ArmModel.load("pulse75")
    q = np.radians(HOME_DEG)
    box = BoxObstacle(
        obstacleType="BOX",
        name="crate",
        sides=Point(x=0.25, y=0.25, z=0.2),
        centerPosition=Position(
            point=Point(x=-0.35, y=-0.7, z=0.1), rotation=Rotation(roll=0, pitch=0, yaw=0)
        ),
    )
    spheres = arm_spheres(arm.dh_frames(q), arm.fk(q)[:3, 3]) + obstacle_spheres([box])
    position, look_at = fit_camera(spheres, VIEW_DIRECTION, FOV_RAD, aspect)
    assert [k for k, (c, r) in enumerate(spheres) if not in_view(position, look_at, c, r, aspect)] == []
    unit = VIEW_DIRECTION / np.linalg.norm(VIEW_DIRECTION)
    assert np.allclose((position - look_at) / np.linalg.norm(position - look_at), unit)  # the usual side
