"""The builder of the browsers' panels: one at a time, the newest browser first, an overdue one before newer
ones, never one that left, and a build that fails does not stop the next."""

from __future__ import annotations

import threading
from collections.abc import Callable

from pendant.ui.page.session_builder import HOLD_BACK_MAX_S, SessionBuilder
from tests.support.waiting import SAFETY_NET_S

WAIT_S = SAFETY_NET_S  # for the builder thread: far more than any build here takes


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def _blocked_builder(clock: FakeClock) -> tuple[SessionBuilder, threading.Event, list[int]]:
    """A builder busy with browser 0 until the event is set; what it built, in order."""
    builder = SessionBuilder(oldest_wait_s=5.0, clock=clock)
    release, started = threading.Event(), threading.Event()
    built: list[int] = []

    def first() -> None:
        started.set()
        release.wait(WAIT_S)
        built.append(0)

    builder.submit(0, first)
    assert started.wait(WAIT_S)
    return builder, release, built


def _record(built: list[int], client_id: int, done: threading.Event | None = None) -> Callable[[], None]:
    def build() -> None:
        built.append(client_id)
        if done is not None:
            done.set()

    return build


def test_the_newest_browser_is_built_first_and_one_that_left_never() -> None:
    clock = FakeClock()
    builder, release, built = _blocked_builder(clock)
    done = threading.Event()
    try:
        builder.submit(1, _record(built, 1, done))
        builder.submit(2, _record(built, 2))
        builder.submit(3, _record(built, 3))
        assert builder.cancel(2)  # it left while waiting
        assert not builder.cancel(0)  # being built: it is not waiting any more
        release.set()
        assert done.wait(WAIT_S)
        assert built == [0, 3, 1]
        assert builder.waiting() == 0
    finally:
        builder.stop()


def test_a_browser_that_has_waited_long_goes_before_newer_ones() -> None:
    clock = FakeClock()
    builder, release, built = _blocked_builder(clock)
    done = threading.Event()
    try:
        builder.submit(1, _record(built, 1))
        clock.now = 6.0  # browser 1 has waited longer than oldest_wait_s
        builder.submit(2, _record(built, 2, done))
        release.set()
        assert done.wait(WAIT_S)
        assert built == [0, 1, 2]
    finally:
        builder.stop()


def test_a_build_that_fails_does_not_stop_the_next() -> None:
    builder = SessionBuilder()
    built: list[int] = []
    done = threading.Event()

    def broken() -> None:
        raise ConnectionError("the browser went away mid-build")

    try:
        builder.submit(1, broken)
        assert _wait_until_idle(builder)
        builder.submit(2, _record(built, 2, done))
        assert done.wait(WAIT_S)
        assert built == [2]
    finally:
        builder.stop()


def _wait_until_idle(builder: SessionBuilder) -> bool:
    idle = threading.Event()
    builder.submit(-1, idle.set)
    return idle.wait(WAIT_S)


def test_builds_wait_while_the_operator_jogs_and_not_longer_than_the_hold_back_limit() -> None:
    clock = FakeClock()
    jogging = threading.Event()
    jogging.set()
    builder = SessionBuilder(clock=clock, hold_back=jogging.is_set)
    built: list[int] = []
    first, second = threading.Event(), threading.Event()
    try:
        builder.submit(1, _record(built, 1, first))
        assert not first.wait(0.3), "a panel was built while the operator held a jog"
        jogging.clear()  # the operator let go
        assert first.wait(WAIT_S)
        jogging.set()
        builder.submit(2, _record(built, 2, second))
        assert not second.wait(0.3)
        clock.now += HOLD_BACK_MAX_S  # a jog held that long: the waiting browser gets its panel all the same
        assert second.wait(WAIT_S)
        assert built == [1, 2]
    finally:
        builder.stop()


def test_while_the_operator_jogs_each_browser_waits_the_hold_back_limit_from_its_own_arrival() -> None:
    """A jog held for minutes while newcomers keep arriving: each is built HOLD_BACK_MAX_S after it came,
    the longest waiting first, not one whole wait per build before it (the queue then grew for as long as
    the hold lasted: benchmarks/classroom.py)."""
    clock = FakeClock()
    jogging = threading.Event()
    jogging.set()
    builder = SessionBuilder(clock=clock, hold_back=jogging.is_set)
    built: list[int] = []
    done = {client: threading.Event() for client in (1, 2, 3)}
    try:
        builder.submit(1, _record(built, 1, done[1]))
        clock.now += HOLD_BACK_MAX_S / 2
        builder.submit(2, _record(built, 2, done[2]))
        builder.submit(3, _record(built, 3, done[3]))
        clock.now += HOLD_BACK_MAX_S / 2  # the first has waited its longest, the others half of it
        assert done[1].wait(WAIT_S)
        assert not done[2].wait(0.3) and not done[3].is_set(), "built before its wait was over"
        clock.now += HOLD_BACK_MAX_S / 2  # and now the other two, the first to come first
        assert done[2].wait(WAIT_S) and done[3].wait(WAIT_S)
        assert built == [1, 2, 3]
    finally:
        builder.stop()


def test_with_browsers_waiting_the_builder_rests_as_long_as_its_last_build_took() -> None:
    """Builds back to back took the interpreter from every other browser's page (benchmarks/churn.py): with
    another browser waiting, the next build starts only after a rest as long as the last build took."""
    clock = FakeClock()
    builder = SessionBuilder(clock=clock)
    built: list[int] = []
    first_done, second = threading.Event(), threading.Event()

    def slow() -> None:
        builder.submit(2, _record(built, 2, second))  # a browser came while this one was being built
        clock.now += 1.0  # a build of a second
        built.append(1)
        first_done.set()

    try:
        builder.submit(1, slow)
        assert first_done.wait(WAIT_S)
        builder.submit(3, lambda: None)  # another comes during the rest: it does not cut it short
        assert not second.wait(0.5), "the next build started at once after a build of a second"
        assert second.wait(WAIT_S)
        assert built == [1, 2]
    finally:
        builder.stop()
