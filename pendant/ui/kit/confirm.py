"""Ask before a destructive action: a question and a Yes / Cancel row, placed where the action's button is.

Built in the panel's GUI (so every test and a screen reader see a plain line and two buttons, not a modal
that may open on another browser). One question at a time: a second request replaces the first.
"""

from __future__ import annotations

from collections.abc import Callable

import viser

from pendant.ui.kit.gui_target import GuiTarget

CONFIRM_OPTIONS = ("Yes", "Cancel")

Action = Callable[[viser.ClientHandle | None], object]


class Confirmation:
    """`ask(question, action)` shows the question; Yes runs `action(client)` for the browser that answered."""

    def __init__(self, target: GuiTarget, label: str = "Confirm") -> None:
        gui = target.gui
        self.question = gui.add_markdown("", visible=False)
        self.buttons = gui.add_button_group(label, options=CONFIRM_OPTIONS, visible=False)
        self._pending: Action | None = None
        self.buttons.on_click(lambda e: self.answer(str(self.buttons.value), e.client))

    @property
    def asking(self) -> bool:
        return self._pending is not None

    def ask(self, question: str, action: Action) -> None:
        self._pending = action
        self.question.content = f"**{question}**"
        self.question.visible = self.buttons.visible = True

    def answer(self, answer: str, client: viser.ClientHandle | None) -> None:
        pending, self._pending = self._pending, None
        self.question.visible = self.buttons.visible = False
        if pending is not None and answer == "Yes":
            pending(client)
