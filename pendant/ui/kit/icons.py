"""viser's icons read once: every browser's panels name ~40 icons, and viser 1.1.1 keeps only the last 32 it
read (`lru_cache(maxsize=32)` over a 1.9 MB zip of ~5,000 icons), so each new browser's panels re-opened the
zip some 30 times (~0.1 s each, 3 of the 3.6 s its panels took to build). Under many browsers connecting and
leaving, a new viewer waited 10-22 s for its page (benchmarks/churn.py).

viser's GUI modules import `svg_from_icon` by name; `cache_viser_icons` gives both modules one unbounded
cache of it (the icons are a closed set of small strings). Not public API: anything unexpected leaves viser as
it is, only slower.
"""

from __future__ import annotations

import functools
import logging
from collections.abc import Callable

import viser._gui_api
import viser._gui_handles
import viser._icons

log = logging.getLogger(__name__)

_MODULES = (viser._icons, viser._gui_api, viser._gui_handles)


def cache_viser_icons() -> bool:
    """Whether viser's icon lookups now go through one unbounded cache (idempotent)."""
    try:
        original: Callable[[str], str] = viser._icons.svg_from_icon
        if getattr(original, "pendant_cached", False):
            return True
        read = getattr(original, "__wrapped__", original)  # under viser's small lru_cache
        cached = functools.cache(read)
        cached.pendant_cached = True  # type: ignore[attr-defined]
        for module in _MODULES:
            if getattr(module, "svg_from_icon", None) is original:
                module.svg_from_icon = cached  # type: ignore[attr-defined]
        return True
    except Exception:  # a viser without these names: its own (slower) lookups still work
        log.debug("viser's icon lookup left as it is", exc_info=True)
        return False
