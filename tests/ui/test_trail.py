"""The TCP trail keeps the last few seconds of the tool's path and fades out when the arm rests."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest
import viser

from pendant.ui.scene.trail import MIN_STEP_M, TRAIL_SECONDS, TcpTrail
from tests.support.ports import free_port


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server
    server.stop()


def test_trail_follows_motion_and_forgets_old_points(server: viser.ViserServer) -> None:
    trail = TcpTrail(server)
    period = 0.125  # exact in binary, so ages compare exactly
    for i in range(48):
        trail.update(i * period, np.array([0.01 * i, 0.0, 0.5]))
    assert trail.n_points == round(TRAIL_SECONDS / period) + 1  # the last three seconds, both ends included
    trail.update(10.0, np.array([0.47, 0.0, 0.5]))  # at rest long after: everything old is gone
    assert trail.n_points == 0


def test_a_resting_arm_adds_no_points(server: viser.ViserServer) -> None:
    trail = TcpTrail(server)
    for i in range(10):
        trail.update(i * 0.1, np.array([0.3, 0.0, 0.5 + MIN_STEP_M * 0.1 * i]))
    assert trail.n_points == 1
