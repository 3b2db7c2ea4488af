"""Two lookups of viser's made once, not once per browser: building one browser's panels took 3.6 s of Python,
3.4 of them in these two (cProfile), and under many browsers connecting and leaving a new viewer waited
10-22 s for its page (benchmarks/churn.py).

- Icons: the panels name ~40 icons, and viser 1.1.1 keeps the last 32 it read (`lru_cache(maxsize=32)`),
  opening its 1.9 MB zip of ~5,000 icons for each (0.1 s to read the zip's directory), so every browser
  re-opened it ~30 times. viser's GUI modules import `svg_from_icon` by name: each gets one that reads the
  zip's directory once and keeps every icon read (a closed set of small strings).
- Property types: every GUI handle worked out its properties' type hints itself (`get_type_hints` per
  handle, ~320 a browser); they depend only on the properties' class, so they are computed once a class.

Not public API: anything unexpected leaves viser as it is, only slower.
"""

from __future__ import annotations

import functools
import logging
import zipfile
from collections.abc import Callable
from typing import Any, get_type_hints

import viser._assignable_props_api
import viser._gui_api
import viser._gui_handles
import viser._icons

log = logging.getLogger(__name__)

_ICON_USERS = (viser._icons, viser._gui_api, viser._gui_handles)
_type_hints = functools.cache(get_type_hints)


@functools.cache
def _icons_zip() -> zipfile.ZipFile:
    return zipfile.ZipFile(viser._icons.ICONS_DIR / "tabler-icons.zip")  # kept open: read from, never written


@functools.cache
def _svg_from_icon(icon_name: str) -> str:
    return _icons_zip().read(f"{icon_name}.svg").decode("utf-8")


def _prop_hints(handle: Any) -> dict[str, Any]:
    return _type_hints(type(handle._impl.props))  # type: ignore[no-any-return]


def cache_viser_lookups() -> None:
    """Icons and property types looked up once (idempotent)."""
    try:
        original: Callable[[str], str] = viser._icons.svg_from_icon
        if not getattr(original, "pendant_cached", False):
            _svg_from_icon.pendant_cached = True  # type: ignore[attr-defined]
            for module in _ICON_USERS:
                if getattr(module, "svg_from_icon", None) is original:
                    module.svg_from_icon = _svg_from_icon  # type: ignore[attr-defined]
        base = viser._assignable_props_api.AssignablePropsBase
        if not isinstance(base.__dict__.get("_prop_hints"), property):
            base._prop_hints = property(_prop_hints)  # type: ignore[assignment,method-assign]
    except Exception:  # a viser without these names: its own (slower) lookups still work
        log.debug("viser's lookups left as they are", exc_info=True)
