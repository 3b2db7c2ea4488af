"""One ghost at a time in a browser's 3D view, and a legend that says which (issue 33: the view was crowded
with the Target tab's ghost, the plan's, the waypoint preview and the replay, all translucent arms).

Each panel that draws a ghost arm takes the stage when it shows one (`show`), which hides the ghost shown
before (its owner's `hide`), and says when its ghost goes (`hidden`). An owner whose ghost was hidden this way
shows it again only when the operator asks for it again (sets a target, picks a step, moves a slider), never
on a redraw. The legend is a hidden element in the panel; the page's script (ghost_legend.js) shows its
text over the 3D view.

The operator may ask for every ghost at once (the Jog tab's "Every ghost" switch, `set_every`): then showing
one hides none, and the legend names each, the newest first; switched off, only the newest stays.
"""

from __future__ import annotations

import html
import threading
from collections.abc import Callable

import viser

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
# Kinds drawn by one and the same arm (the target's ghost shows a target or a plan; the check playback
# moves the waypoint preview): with every ghost shown, a kind replaces its sibling in the legend.
ARM_OF = {"target": "target", "plan": "target", "waypoint": "preview", "check": "preview", "replay": "replay"}


def legend_entry(kind: str, *, blocked: bool = False) -> str:
    """One ghost's line of the legend (a hidden element: the script shows its text over the view); `blocked`:
    the target ghost is red (the target cannot be reached or hits something)."""
    words, colour = KINDS[kind]
    if blocked:
        words, colour = f"{words} (blocked)", "#f22626"
    return f'<div hidden data-ghost-legend="Ghost: {html.escape(words)}" data-ghost-colour="{colour}"></div>'


def render_legend(kinds: list[str], *, blocked: bool = False) -> str:
    """The legend's element for the ghosts `kinds` shown, the newest first (`blocked`: the target's)."""
    if not kinds:
        return inset('<div hidden data-ghost-legend=""></div>')
    return inset("".join(legend_entry(kind, blocked=blocked and kind == "target") for kind in kinds))


class GhostStage:
    """Which of a browser's ghosts are shown (`shown`: the newest, a key of KINDS, or None)."""

    def __init__(self, target: GuiTarget | None = None) -> None:
        self._lock = threading.Lock()
        self._hides: dict[str, Callable[[], None]] = {}
        self._shown: list[str] = []  # the newest last
        self.every = False
        self.blocked = False
        self._target = target
        self.switch: viser.GuiCheckboxHandle | None = None  # "Every ghost", once added
        self.legend = target.gui.add_html(render_legend([])) if target is not None else None

    @property
    def shown(self) -> str | None:
        return self._shown[-1] if self._shown else None

    @property
    def all_shown(self) -> list[str]:
        """Every ghost shown, the newest first (more than one only with `every`)."""
        return self._shown[::-1]

    def add_switch(self) -> None:
        """The "Every ghost" switch, where the panel is being built (the Jog tab, by Fit view)."""
        if self._target is None:
            return
        self.switch = switch = self._target.gui.add_checkbox(
            "Every ghost",
            initial_value=False,
            hint="Show every ghost at once (target, plan, waypoint, replay); off: only the newest",
        )
        switch.on_update(lambda _: self.set_every(switch.value))

    def register(self, kind: str, hide: Callable[[], None]) -> None:
        """`hide` hides that ghost when another takes the stage; it must not call the stage back."""
        if kind not in KINDS:
            raise ValueError(f"unknown ghost {kind!r}: one of {', '.join(KINDS)}")
        self._hides[kind] = hide

    def show(self, kind: str, *, blocked: bool = False) -> None:
        """`kind`'s ghost is shown now: unless every ghost is asked for, the one shown before is hidden."""
        with self._lock:
            before = [k for k in self._shown if k != kind]
            others = [k for k in before if ARM_OF[k] != ARM_OF[kind]]
            self._shown = [*others, kind] if self.every else [kind]
            if kind == "target" or not self.every:
                self.blocked = blocked
            self._draw()
        if not self.every:
            self._hide(before, keep=kind)

    def hidden(self, kind: str) -> None:
        """`kind`'s ghost went (its owner hid it): the legend drops it."""
        with self._lock:
            if kind in self._shown:
                self._shown.remove(kind)
                if kind == "target" or not self._shown:
                    self.blocked = False
                self._draw()

    def set_every(self, every: bool) -> None:
        """Every ghost at once, or (off) only the newest: the others are hidden now."""
        with self._lock:
            self.every = every
            older, self._shown = self._shown[:-1], self._shown[-1:]
            if "target" in older:
                self.blocked = False
            self._draw()
        self._hide(older, keep=self.shown)

    def _hide(self, kinds: list[str], keep: str | None) -> None:
        kept = self._hides.get(keep) if keep is not None else None
        for kind in kinds:
            hide = self._hides.get(kind)
            if hide is not None and hide is not kept:  # one owner's two kinds: its own to switch
                hide()

    def _draw(self) -> None:
        if self.legend is None:
            return
        content = render_legend(self.all_shown, blocked=self.blocked)
        if self.legend.content != content:
            self.legend.content = content
