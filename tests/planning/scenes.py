"""Kept for tests/browser/test_program_check.py until the browser suite's rework: the scene lives in
tests/support/preflight_scene.py (tests import only tests/support)."""

from tests.support.preflight_scene import (
    BOX_NAME,
    LEFT_DEG,
    RIGHT_DEG,
    box_in_the_way,
    swing_program,
    waypoint,
)

__all__ = ["BOX_NAME", "LEFT_DEG", "RIGHT_DEG", "box_in_the_way", "swing_program", "waypoint"]
