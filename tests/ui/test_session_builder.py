"""The builder of the browsers' panels: one at a time, the newest browser first, an overdue one before newer
ones, never one that left, and a build that fails does not stop the next."""

from __future__ import annotations

import threading

from pendant.ui.page.session_builder import SessionBuilder

WAIT_S = 10.0  # for the builder thread: far more than any build here takes


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


def _record(built: list[int], client_id: int, done: threading.Event | None = None):  # type: ignore[no-untyped-def]
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
