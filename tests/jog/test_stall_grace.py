"""The deadman's watchdog after the process stood still (pendant.jog.deadman.StallGrace): one late wake
gives the hold line its grace before the judgement; a process late on every wake still gets judged every
other wake, so a browser gone silent is never kept moving by stalls. Wake times as the watchdog reads them;
the real thing (a pendant held still 200 ms every second): tests/ui/test_hold_through_stalls.py."""

from __future__ import annotations

from pendant.jog.deadman import STALL_GRACE_S, WATCHDOG_STALL_S, StallGrace

PERIOD_S = 0.01
LATE_S = PERIOD_S + WATCHDOG_STALL_S + 0.1  # a wake after a 150 ms stall


def test_wakes_on_time_are_judged_at_once() -> None:
    wakes = StallGrace(PERIOD_S, 0.0)
    assert not any(wakes.woke_late(k * PERIOD_S) for k in range(1, 100))


def test_a_late_wake_is_graced_once_then_judged_on_time() -> None:
    wakes = StallGrace(PERIOD_S, 0.0)
    assert wakes.woke_late(LATE_S)
    wakes.restart(LATE_S + STALL_GRACE_S)
    assert not wakes.woke_late(LATE_S + STALL_GRACE_S + PERIOD_S)


def test_late_on_every_wake_is_graced_every_other_wake_only() -> None:
    """A process that stalls on every wake: the judgement comes at the latest every second wake."""
    wakes = StallGrace(PERIOD_S, 0.0)
    now, graced = 0.0, []
    for _ in range(10):
        now += LATE_S
        graced.append(wakes.woke_late(now))
        if graced[-1]:
            now += STALL_GRACE_S
            wakes.restart(now)
    assert graced == [True, False] * 5
