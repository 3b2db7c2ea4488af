"""The status block while the arm moves (issue 37): the joints and the TCP go to the operator's browser at
most ten times a second and to a viewer's four times (the refresh reads at 30 Hz, and each change was the
whole block to every browser), while a change of the motion state, a fault or an output is sent the moment
it is read; the last values reach the browser once the arm is still. A real viser server on loopback, the
block as its browsers are sent it."""

from __future__ import annotations

import time
from collections.abc import Iterator

import numpy as np
import pytest
import viser

from pendant.controller import MotionStatus, SignalLevel
from pendant.sim import SimController
from pendant.ui.kit.commands import CommandRunner
from pendant.ui.kit.readout_rates import OPERATOR_READOUT_S, VIEWER_READOUT_S
from pendant.ui.kit.snapshot import Snapshot
from pendant.ui.page.status_panel import StatusPanel
from tests.support.ports import LOOPBACK, free_port


@pytest.fixture
def panel(sim: SimController) -> Iterator[StatusPanel]:
    server = viser.ViserServer(host=LOOPBACK, port=free_port(), verbose=False)
    runner = CommandRunner(sim)
    try:
        yield StatusPanel(server, "Simulator · pulse75", runner)
    finally:
        runner.shutdown()
        server.stop()


def at(
    j1_deg: float, status: MotionStatus = MotionStatus.RUNNING, outputs: dict[int, SignalLevel] | None = None
) -> Snapshot:
    q = np.radians([j1_deg, -90.0, 90.0, -90.0, -90.0, 0.0])
    return Snapshot(
        taken_at=time.monotonic(), online=True, motion_status=status, q=q, outputs=dict(outputs or {})
    )


def test_moving_joints_go_out_ten_times_a_second_a_new_state_at_once(panel: StatusPanel) -> None:
    panel.show(at(10.0))
    assert "10.0°" in panel.content
    panel.show(at(11.0))  # a tick later (1/30 s): only the values moved
    assert "10.0°" in panel.content, "the joints were sent again within a tenth of a second"
    panel.show(at(12.0, MotionStatus.ERROR))  # a fault: the block says so now
    assert ">ERROR<" in panel.content and "12.0°" in panel.content
    panel.show(at(13.0, MotionStatus.ERROR, outputs={1: SignalLevel.HIGH}))  # an output set: now
    assert "13.0°" in panel.content
    time.sleep(OPERATOR_READOUT_S * 1.5)
    panel.show(at(14.0, MotionStatus.ERROR, outputs={1: SignalLevel.HIGH}))  # the next tick after the pause
    assert "14.0°" in panel.content, "the joints were not sent a tenth of a second later"


def test_a_viewer_gets_the_moving_joints_four_times_a_second_a_new_state_at_once(panel: StatusPanel) -> None:
    panel.viewer = True  # a browser without control (the session sets it with the role)
    sent_at = time.monotonic()  # before the panel's own reading of the clock: the bracket errs safe
    panel.show(at(10.0))
    time.sleep(OPERATOR_READOUT_S * 1.5)  # the operator's block would have the new joints by now
    panel.show(at(11.0))
    if time.monotonic() - sent_at < VIEWER_READOUT_S:  # bracketed by this test's own clock
        assert "10.0°" in panel.content, "a viewer was sent the joints again within a quarter of a second"
    panel.show(at(12.0, MotionStatus.ERROR))  # a fault: every browser is told now
    assert ">ERROR<" in panel.content and "12.0°" in panel.content
    time.sleep(VIEWER_READOUT_S * 1.5)
    panel.show(at(13.0, MotionStatus.ERROR))
    assert "13.0°" in panel.content, "a viewer's joints were not sent a quarter of a second later"
