"""Fit view's camera (pendant/ui/scene/framing.py): every sphere of the work projects inside the view, for a
wide desk view, an upright tablet's narrow one and a phone's, with the pendant's usual viewing direction."""

from __future__ import annotations

import numpy as np
import pytest

from pendant.controller.cell_types import BoxObstacle
from pendant.controller.types import Point, Position, Rotation
from pendant.kinematics import ArmModel
from pendant.ui.page.view_fit import VIEW_DIRECTION
from pendant.ui.scene.framing import arm_spheres, fit_camera, obstacle_spheres
from tests.support.pinhole import FOV_RAD, HOME_DEG, in_view


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
