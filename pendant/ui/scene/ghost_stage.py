"""One ghost at a time in a browser's 3D view, and a legend that says which (issue 33: the view was crowded
with the Target tab's ghost, the plan's, the waypoint preview and the replay, all translucent arms).

Each panel that draws a ghost arm takes the stage when it shows one (`show`), which hides the ghost shown
before (its owner's `hide`), and says when its ghost goes (`hidden`). An owner whose ghost was hidden this way
shows it again only when the operator asks for it again (sets a target, picks a step, moves a slider), never
on a redraw. The legend is a hidden element in the panel; the page's script (ghost_legend.js) shows its
text over the 3D view.
"""

from __future__ import annotations

import html
import threading
from collections.abc import Callable

from pendant.ui.kit.gui_target import GuiTarget
from pendant.ui.kit.html import inset

# What each ghost is, in the legend's words, and the colour it is drawn in.
KINDS = {
    "target": ("target", "#4080ff"),
    "plan": ("plan", "#4080ff"),
    "waypoint": ("waypoint", "#33bf59"),
    "check": ("check playback", "#33bf59"),
    "replay": ("replay", "#8c59d9"),
}


def render_legend(kind: str | None, *, blocked: bool = False) -> str:
    """The legend's element (hidden: the script shows its text over the view); `blocked`: the target ghost
    is red (the target cannot be reached or hits something)."""
    if kind is None:
        return inset('<div hidden data-ghost-legend=""></div>')
    words, colour = KINDS[kind]
    if blocked:
        words, colour = f"{words} (blocked)", "#f22626"
    return inset(
        f'<div hidden data-ghost-legend="Ghost: {html.escape(words)}" data-ghost-colour="{colour}"></div>'
    )


class GhostStage:
    """Which of a browser's ghosts is shown (`shown`: a key of KINDS, or None)."""

    def __init__(self, target: GuiTarget | None = None) -> None:
        self._lock = threading.Lock()
        self._hides: dict[str, Callable[[], None]] = {}
        self.shown: str | None = None
        self.blocked = False
        self.legend = target.gui.add_html(render_legend(None)) if target is not None else None

    def register(self, kind: str, hide: Callable[[], None]) -> None:
        """`hide` hides that ghost when another takes the stage; it must not call the stage back."""
        if kind not in KINDS:
            raise ValueError(f"unknown ghost {kind!r}: one of {', '.join(KINDS)}")
        self._hides[kind] = hide

    def show(self, kind: str, *, blocked: bool = False) -> None:
        """`kind`'s ghost is shown now: the one shown before is hidden."""
        with self._lock:
            before, self.shown, self.blocked = self.shown, kind, blocked
            self._draw()
        hide = self._hides.get(before) if before is not None else None
        if hide is not None and hide is not self._hides.get(kind):  # one owner's two kinds: its own to switch
            hide()

    def hidden(self, kind: str) -> None:
        """`kind`'s ghost went (its owner hid it): the legend clears if it was the one shown."""
        with self._lock:
            if self.shown == kind:
                self.shown, self.blocked = None, False
                self._draw()

    def _draw(self) -> None:
        if self.legend is None:
            return
        content = render_legend(self.shown, blocked=self.blocked)
        if self.legend.content != content:
            self.legend.content = content
