"""The objects `pendant` builds to start (the planner, the models, the page's panels) kept out of the
garbage collector's way while it serves (issue #32).

A full collection walks every object of the process in one call that holds every thread, the ones that send
Freeze included: 64-105 ms in a page's process (160,000 objects at start; measured on this 2-core machine
under load), and loading a replay makes enough objects that stay to set one off. Those start-up objects live
as long as the pendant does: frozen (`gc.freeze`), collections walk only what came after them, and a full
one takes well under a millisecond. They are given back to the collector when the pendant stops, so that
the exit's collections still see them.
"""

from __future__ import annotations

import gc


def settle() -> None:
    """Collect once (what the start-up left is not kept), then freeze what remains: call once started."""
    gc.collect()
    gc.freeze()


def unsettle() -> None:
    """Give the frozen objects back to the collector (the pendant is stopping)."""
    gc.unfreeze()
