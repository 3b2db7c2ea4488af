"""Whether a tab's panel is on a browser's screen, as its page says (client_page.js, section 11).

A browser on one tab gets no use from another tab's live drawings, yet the Dashboard's three plots and its
motor table went to every browser at each refresh: with 60 viewers on the Jog tab, sent sixty times over
for nobody (issue 37). The tab holds an empty marker naming two hidden buttons; the page clicks the first
when the marker comes into view and the second when it leaves (a tab switched, the page's panel folded).
`shown` starts False in a browser (no tab but the first is open at load), True on the server's own GUI
(headless tests: no page to say so, so everything is drawn).
"""

from __future__ import annotations

from collections.abc import Callable

import viser

from pendant.ui.kit.gui_target import GuiTarget


class TabWatch:
    """Add inside the tab (first): `shown` says whether its panel is on screen; `on_change(shown)` runs
    (on viser's callback pool) when that changes."""

    def __init__(self, target: GuiTarget, on_change: Callable[[bool], None]) -> None:
        self.shown = not isinstance(target, viser.ClientHandle)
        self._on_change = on_change
        came = target.gui.add_button("Tab shown", visible=False)
        went = target.gui.add_button("Tab hidden", visible=False)
        marker = f'data-tab-shown="{came._impl.uuid}" data-tab-hidden="{went._impl.uuid}"'
        self.marker = target.gui.add_html(f'<div {marker} style="height:1px"></div>')
        came.on_click(lambda _: self._set(True))
        went.on_click(lambda _: self._set(False))

    def _set(self, shown: bool) -> None:
        if shown != self.shown:
            self.shown = shown
            self._on_change(shown)
