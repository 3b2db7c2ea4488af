"""The Dashboard's samples: the page's own refresh step ticked on the fake clock."""

from __future__ import annotations

from pendant.controller import Pose
from pendant.controller.types import MotorStatus
from pendant.sim import FakeClock
from pendant.ui.app import PendantUI

SAMPLE_PERIOD_S = 0.1  # the refresh loop samples the motors at 10 Hz
MOVE = Pose(angles=[40.0, -70.0, 30.0, -90.0, -90.0, 20.0])  # a move that turns every joint


def sample(pendant_ui: PendantUI, clock: FakeClock, count: int) -> list[list[MotorStatus]]:
    """`count` ticks of the refresh loop's dashboard step, SAMPLE_PERIOD_S apart; the readings taken."""
    readings = []
    for _ in range(count):
        clock.advance(SAMPLE_PERIOD_S)
        pendant_ui.refresh_dashboard()
        assert pendant_ui.telemetry.latest is not None
        readings.append(pendant_ui.telemetry.latest)
    return readings
