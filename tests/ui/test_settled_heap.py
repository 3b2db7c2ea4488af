"""No garbage collection holds up a Freeze (issue #32): in a page's process, once `pendant` has started
(pendant.cli.heap.settle), a full collection keeps the other threads (Freeze's) waiting less than the 50 ms
the issue allows anything; before, it walked the whole start-up's heap in one call: 64-105 ms. The page
in-process on loopback, as `pendant` builds it, with one browser's panels."""

from __future__ import annotations

import gc

import pytest

from pendant.cli import heap
from pendant.sim import SimController
from tests.support.gil import longest_hold_ms
from tests.support.pages import headless_session, pendant_page

# CPU time while the other threads wait (tests/support/gil.py): run alone, after the rest.
pytestmark = pytest.mark.measures

FREEZE_DELAY_MS = 50.0  # the bound
TRIES = 3


def test_a_full_collection_in_a_started_page_never_holds_up_the_other_threads(sim: SimController) -> None:
    with pendant_page(sim, sim.arm) as page:
        headless_session(page)
        heap.settle()
        try:
            held = [longest_hold_ms(gc.collect)[0] for _ in range(TRIES)]
        finally:
            heap.unsettle()
    assert max(held) < FREEZE_DELAY_MS, f"the other threads waited up to {max(held):.0f} ms: {held}"
