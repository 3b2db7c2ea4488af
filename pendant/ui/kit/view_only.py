"""A viewer's page: the commanding controls greyed out, each saying why on hover (never a button that looks
active and silently does nothing)."""

from __future__ import annotations

import viser

VIEW_ONLY_HINT = "View only: another browser has control. Press Take control at the top to use this."


class ViewOnly:
    """Disables (or, for button groups viser cannot disable, hides) one browser's commanding controls, and
    swaps each one's tooltip for VIEW_ONLY_HINT while they are; its own tooltip comes back with control."""

    def __init__(self) -> None:
        self._hints: dict[str, str | None] = {}  # a control's own tooltip, by its id, while it is locked

    def apply(self, handle: viser.GuiInputHandle, locked: bool) -> None:
        if isinstance(handle, viser.GuiButtonGroupHandle):
            if handle.visible == locked:
                handle.visible = not locked
            return
        if handle.disabled != locked:  # each assignment is a message to the browser
            handle.disabled = locked
        key = handle._impl.uuid  # viser's own id of the control
        if locked and key not in self._hints:
            self._hints[key] = handle.hint
            handle.hint = VIEW_ONLY_HINT
        elif not locked and key in self._hints:
            handle.hint = self._hints.pop(key)
