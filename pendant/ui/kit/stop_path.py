"""The page's stop buttons (Freeze, Esc, Protective stop, program Stop) apart from viser's callback pool.

viser 1.1.1 runs a plain callback on one thread pool (32 threads) shared by every button of every browser,
and runs an `async def` callback on its event loop as the click's message arrives. A viewer clicking a slow
button 40 times filled that pool and Freeze waited behind it, for good. So a stop's callback is async: on
the event loop it only hands the press to the runner's stop thread (nothing else runs there), which sends
the stop on the urgent thread as before.
"""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import Callable, Coroutine
from concurrent.futures import Future
from typing import Any, Protocol

import viser

Press = Callable[[viser.ClientHandle | None], object]


class PressRunner(Protocol):
    def press(self, pressed: Callable[[], object]) -> Future[object] | None: ...


class _Event(Protocol):
    @property
    def client(self) -> viser.ClientHandle | None: ...


def on_stop_press(runner: PressRunner, press: Press) -> Callable[[Any], Coroutine[Any, Any, None]]:
    """A click (or hotkey) callback that runs `press(client)` on the stop thread, never on viser's pool."""

    async def pressed(event: _Event) -> None:
        client = event.client
        handed = runner.press(lambda: press(client))
        if handed is not None:  # awaited by this click's own task only: the loop goes on meanwhile
            with contextlib.suppress(Exception):  # logged by the runner
                await asyncio.wrap_future(handed)

    return pressed
