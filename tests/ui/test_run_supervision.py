"""The page that started a run supervises it (issue 31): its browser's page closing during a motion pauses
the run within 0.5 s (the arm frozen, the place kept), and only a browser with control can Resume it.

The page in-process on loopback. The first test's browser is a bare websocket (what a browser sends; its
close is what a closed tab sends) and the simulator runs on the real clock, so the arm really moves while
the page closes. The second test's browsers are stand-ins pressing the banner's buttons."""

from __future__ import annotations

import asyncio
import time

import numpy as np
import pytest

from pendant.controller import MotionStatus, Pose, SignalLevel
from pendant.program import OutputStep, RunState, WaitStep, Waypoint
from pendant.sim import MonotonicClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.recovery import Action
from pendant.ui.page.session import ClientSession
from tests.support.doubles import OPERATOR, VIEWER, FakeBrowser
from tests.support.headless_viewer import open_viewer
from tests.support.pages import pendant_page
from tests.support.programs import move, program_of
from tests.support.waiting import wait_until

PAUSED_WITHIN_S = 0.5  # issue 31: "the run pauses within 0.5 s"
FAR_DEG = [120.0, -90.0, 90.0, -90.0, -90.0, 0.0]
SLOW_PERCENT = 5.0  # 120 degrees at 5 %: seconds of motion, still moving when the page closes
MOVING_FOR_S = 0.5
HELD_S = 1.0
STILL_TOL_DEG = 0.01
TIMEOUT_S = 30.0


@pytest.mark.measures  # the 0.5 s is the figure: measured alone, not beside another worker
def test_the_supervising_page_closed_during_a_motion_pauses_the_run_within_half_a_second() -> None:
    sim = SimController("pulse75", MonotonicClock())
    far = Waypoint(name="Far", pose=Pose(angles=FAR_DEG), position=sim.get_position())
    with pendant_page(sim, sim.arm) as page:
        page.programs.open_uploaded(program_of(move(far, speed=SLOW_PERCENT)))
        closed_for_s = asyncio.run(close_the_page_mid_motion(page, sim))

        assert closed_for_s <= PAUSED_WITHIN_S, f"the arm moved on for {closed_for_s:.2f} s"
        paused = lambda: page.programs.progress.state is RunState.PAUSED  # noqa: E731
        wait_until(paused, TIMEOUT_S, "the run paused")  # the runner's next look, after the freeze
        assert "page closed while the program ran" in page.programs.progress.message
        held = np.array(sim.get_pose().angles)
        time.sleep(HELD_S)
        np.testing.assert_allclose(sim.get_pose().angles, held, atol=STILL_TOL_DEG)
        assert not np.allclose(held, FAR_DEG, atol=1.0)


async def close_the_page_mid_motion(page: PendantUI, sim: SimController) -> float:
    """Join, run the program as this browser, close the page mid-move: seconds until the arm stood still."""
    ws = await open_viewer(page.server.get_port())
    try:
        await asyncio.to_thread(wait_until, lambda: page.desk.operator is not None, TIMEOUT_S, "the join")
        page.programs.start_run(supervisor=page.desk.operator)
        moving = lambda: sim.get_motion_status() is MotionStatus.RUNNING  # noqa: E731
        await asyncio.to_thread(wait_until, moving, TIMEOUT_S, "the run moving the arm")
        await asyncio.sleep(MOVING_FOR_S)
        assert moving()
    finally:
        closed_at = time.monotonic()
        await ws.close()
    await asyncio.to_thread(wait_until, lambda: not moving(), TIMEOUT_S, "the arm stopping", 0.005)
    return time.monotonic() - closed_at


def test_only_a_browser_with_control_resumes_a_run_its_page_left(
    pendant_ui: PendantUI, ui: ClientSession
) -> None:
    """OPERATOR's page runs a program and closes; VIEWER, without control, cannot Resume it; once it has
    control, it can."""
    programs = pendant_ui.programs
    programs.open_uploaded(program_of(WaitStep(ms=20_000), OutputStep(port=1, level=SignalLevel.HIGH)))
    programs.start_run(supervisor=OPERATOR)
    wait_until(lambda: programs.progress.state is RunState.RUNNING, TIMEOUT_S, "the run")
    third = FakeBrowser(3)
    pendant_ui.desk.join(third.client_id)
    pendant_ui.disconnect(FakeBrowser(OPERATOR).handle)  # its control passes on
    wait_until(lambda: programs.progress.state is RunState.PAUSED, TIMEOUT_S, "the pause")
    assert programs.runner.join(TIMEOUT_S)  # the paused run's worker has ended (as long before a click)
    assert ui.banner is not None
    operator = pendant_ui.desk.operator
    assert operator in (VIEWER, third.client_id)
    without_control = FakeBrowser(third.client_id if operator == VIEWER else VIEWER)

    ui.banner.act(Action.RESUME, "Resume program", without_control.handle)

    assert programs.progress.state is RunState.PAUSED
    assert any("Resume program (banner) refused" in note for note in without_control.notifications)
    ui.banner.act(Action.RESUME, "Resume program", FakeBrowser(operator).handle)
    wait_until(lambda: programs.progress.state is RunState.RUNNING, TIMEOUT_S, "the resumed run")
    programs.stop()
    assert programs.runner.join(TIMEOUT_S)
