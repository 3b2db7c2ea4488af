"""A program step's speed outside 1-100 % is refused where it is entered, with the range (issue 22): a step at
0 % used to be accepted by the editor and fail only when run."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from pendant.program.models import MoveStep


@pytest.mark.parametrize("speed", [0.0, 0.5, 100.5, -10.0])
def test_a_step_speed_outside_1_to_100_percent_is_refused_with_the_range(speed: float) -> None:
    with pytest.raises(ValidationError, match="Speed must be 1 to 100 %"):
        MoveStep(waypoint="P1", speed=speed)


@pytest.mark.parametrize("speed", [1.0, 42.0, 100.0])
def test_a_step_speed_inside_the_range_is_kept(speed: float) -> None:
    assert MoveStep(waypoint="P1", speed=speed).speed == speed
