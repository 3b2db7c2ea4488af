"""A held jog outlasts the pendant's own stalls, and the deadman still cuts a browser that goes silent (issue
37). With 100 browsers' panels a full garbage collection held the whole pendant 114-139 ms; the operator's
confirmations (every 50 ms) then waited unread in the hold line's socket, and when the process went on, the
deadman's watchdog could look before the line had read them: "no confirmation from the page for 200 ms",
5 cuts in 30 s at half a core.

A real `pendant` process on loopback whose interpreter lock is held 200 ms every second
(tests/support/stalling_pendant.py: nothing of the process runs meanwhile); the operator, a process of its
own, holds J1+ over the hold line for 8 s: its only stop is its release. Then it holds again and goes silent
without a release (a browser that died): the deadman stops the arm."""

from __future__ import annotations

import asyncio
import time
from pathlib import Path

import pytest

from tests.support import stalling_pendant
from tests.support.headless_viewer import (
    drain,
    gui_update,
    open_hold_line,
    open_viewer,
    read_jog_pad,
)
from tests.support.holds import DEADMAN, RELEASED, hold_j1, j1_stops_since
from tests.support.launchers import Pendant, running_pendant_ui

pytestmark = [pytest.mark.slow, pytest.mark.measures]  # confirmations every 50 ms against a 200 ms deadman

STALL_MS, EVERY_MS = 200, 1000  # longer than the deadman's 200 ms with the 50 ms between confirmations
HOLD_S = 8.0  # seven stalls
JOG_SPEED_PERCENT = 5.0  # J1 at 6 deg/s
MIN_MOVED_DEG = 20.0  # 48 deg if the whole hold moves it
OPERATOR_LATE_S = 0.15  # the test's own process sent a confirmation this late: it, not the pendant, was late
PAGE_TIMEOUT_S = 120.0  # generous: the page's panels through the stalls; not what is tested
EVENT_TIMEOUT_S = 10.0
SILENT_HOLD_S = 1.0
STILL_DEG = 0.01


async def _hold(pendant: Pendant, seconds: float, release: bool) -> tuple[list[str], float, float]:
    """A browser comes and holds J1+ for `seconds` over the hold line, released or not: its stops, J1's
    travel, the largest gap between two of this side's sends (s)."""
    operator = await open_viewer(pendant.ui_port)
    try:
        pad = await read_jog_pad(operator, PAGE_TIMEOUT_S)
        draining = asyncio.create_task(drain(operator))
        await operator.send(gui_update(pad.speed, JOG_SPEED_PERCENT))
        line = await open_hold_line(pad)
        since = time.time()
        j1 = (await asyncio.to_thread(pendant.pose))[0]
        held = await hold_j1(line, pad, seconds, release)
        stops = await asyncio.to_thread(j1_stops_since, pendant, since, EVENT_TIMEOUT_S)
        moved = (await asyncio.to_thread(pendant.pose))[0] - j1
        await line.close()
        draining.cancel()
        return stops, moved, held.largest_gap_s
    finally:
        await operator.close()


def _still(pendant: Pendant) -> bool:
    before = pendant.pose()[0]
    time.sleep(STALL_MS / 1000.0 + EVERY_MS / 1000.0)  # a stall and more: a moving arm moves meanwhile
    return abs(pendant.pose()[0] - before) < STILL_DEG


def test_a_held_jog_outlasts_the_pendants_stalls_and_the_deadman_still_cuts_a_silent_browser() -> None:
    launcher = (str(Path(stalling_pendant.__file__)), str(STALL_MS), str(EVERY_MS))
    with running_pendant_ui(launcher=launcher) as pendant:
        stops, moved, gap = asyncio.run(_hold(pendant, HOLD_S, release=True))
        assert gap < OPERATOR_LATE_S, (
            f"this test's operator sent {gap:.3f} s apart: it, not the pendant, was late"
        )
        assert stops == [RELEASED], f"a hold through the pendant's stalls ended: {stops}"
        assert moved > MIN_MOVED_DEG, f"J1 went {moved:.1f} deg in an {HOLD_S:.0f} s hold"

        silent, _, _ = asyncio.run(_hold(pendant, SILENT_HOLD_S, release=False))
        assert len(silent) == 1 and silent[0].startswith(DEADMAN), f"a browser gone silent: {silent}"
        assert _still(pendant), "the arm still moved after the deadman's cut"
