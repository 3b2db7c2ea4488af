"""A feature the controller may lack (older firmware answers 404 to SDK 1.8 operations): its controls are
greyed out and a line says why, instead of each press failing. Known from a read (`show`) or learnt from a
command's own 404 (`learn`); a viewer's page greys them out too."""

from __future__ import annotations

from collections.abc import Sequence
from concurrent.futures import Future

import viser

from pendant.controller.errors import Unsupported


class Availability:
    def __init__(self, gui: viser.GuiApi, feature: str, handles: Sequence[viser.GuiInputHandle]) -> None:
        self._feature = feature
        self._handles = tuple(handles)
        self.note = gui.add_markdown("", visible=False)
        self.locked = False  # a viewer's page
        self._read: str | None = None  # why the controller lacks it, from a read
        self._learnt: str | None = None  # from a command's reply

    @property
    def reason(self) -> str | None:
        """The controller's words for why the feature is missing, or None when it has it."""
        return self._read or self._learnt

    def set_locked(self, locked: bool) -> None:
        self.locked = locked
        self._refresh()

    def show(self, unsupported: str | None) -> None:
        """What the latest read said: the controller's message when it lacks the feature, else None."""
        if unsupported != self._read:
            self._read = unsupported
            self._refresh()

    def learn(self, future: Future[object]) -> Future[object]:
        """A command of this feature answered 404: the feature is missing, from now on."""

        def done(f: Future[object]) -> None:
            error = f.exception()
            if isinstance(error, Unsupported):
                self._learnt = error.message
                self._refresh()

        future.add_done_callback(done)
        return future

    def _refresh(self) -> None:
        reason = self.reason
        disabled = self.locked or reason is not None
        for handle in self._handles:
            if handle.disabled != disabled:
                handle.disabled = disabled
        text = f"**{self._feature} unavailable:** {reason}" if reason else ""
        if self.note.content != text:
            self.note.content = text
        if self.note.visible != bool(reason):
            self.note.visible = bool(reason)
