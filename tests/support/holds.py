"""A jog held over the page's hold line as the page's worker holds it (a confirmation every 1 / HOLD_HZ s),
and the jog's stops as the pendant's event log names them ("Jog J1+ stopped: released")."""

from __future__ import annotations

import asyncio
import time
from dataclasses import dataclass

import websockets

from tests.support.headless_viewer import HOLD_HZ, JogPad, line_hold, line_release
from tests.support.launchers import Pendant
from tests.support.waiting import wait_until

STOPPED = "Jog J1+ stopped"
RELEASED = f"{STOPPED}: released"
DEADMAN = f"{STOPPED}: deadman"


@dataclass(frozen=True)
class Held:
    started: float  # monotonic
    ended: float
    largest_gap_s: float  # this side's own, between two confirmations sent


async def hold_j1(
    line: websockets.ClientConnection, pad: JogPad, seconds: float, release: bool = True
) -> Held:
    """J1+ held for `seconds`, then released (or not: a browser gone silent)."""
    started = sent = time.monotonic()
    largest_gap = 0.0
    while sent < started + seconds:
        await line.send(line_hold(pad.hold))
        now = time.monotonic()
        largest_gap, sent = max(largest_gap, now - sent), now
        await asyncio.sleep(1.0 / HOLD_HZ)
    if release:
        await line.send(line_release(pad.hold))
    return Held(started, time.monotonic(), largest_gap)


def j1_stops_since(pendant: Pendant, since: float, timeout_s: float) -> list[str]:
    """The J1+ jog's stops in the event log since `since` (epoch s), once there is one (the log is written
    by a thread of its own)."""
    wait_until(lambda: bool(pendant.events(STOPPED, since)), timeout_s, "the hold's stop in the event log")
    return pendant.events(STOPPED, since)
