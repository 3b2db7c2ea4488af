"""Ask before a destructive action: a dialog (a viser modal) with the question and Yes / Cancel, on the page
of the browser whose panel asked. The dialog takes the focus and covers the panel, so it cannot be missed, as
an inline line could (issue 33: a missed "Discard the unsaved changes?" after New sent the next Records into
the old program). One question at a time: a second request replaces the first.
"""

from __future__ import annotations

from collections.abc import Callable

import viser
from viser._gui_handles import GuiModalHandle  # viser 1.1.1 does not export it

from pendant.ui.kit.gui_target import GuiTarget

CONFIRM_OPTIONS = ("Cancel", "Yes")  # Cancel first: a stray Enter on the first button loses nothing

Action = Callable[[viser.ClientHandle | None], object]


class Confirmation:
    """`ask(question, action)` opens the dialog; Yes runs `action(client)` for the browser that answered."""

    def __init__(self, target: GuiTarget, label: str = "Confirm") -> None:
        self._target = target
        self._label = label
        self._modal: GuiModalHandle | None = None
        self._question: viser.GuiMarkdownHandle | None = None
        self._buttons: viser.GuiButtonGroupHandle | None = None
        self._pending: Action | None = None

    @property
    def question(self) -> viser.GuiMarkdownHandle:
        """The last question's text (in its dialog; not visible once answered)."""
        if self._question is None:
            raise LookupError("nothing has been asked yet")
        return self._question

    @property
    def buttons(self) -> viser.GuiButtonGroupHandle:
        """The last question's Cancel / Yes."""
        if self._buttons is None:
            raise LookupError("nothing has been asked yet")
        return self._buttons

    @property
    def asking(self) -> bool:
        return self._pending is not None

    def ask(self, question: str, action: Action, title: str = "Are you sure?") -> None:
        self._close()
        self._pending = action
        gui = self._target.gui
        with gui.add_modal(title) as modal:
            self._question = gui.add_markdown(f"**{question}**")
            buttons = self._buttons = gui.add_button_group(self._label, options=CONFIRM_OPTIONS)
        self._modal = modal
        buttons.on_click(lambda e: self.answer(str(buttons.value), e.client))

    def answer(self, answer: str, client: viser.ClientHandle | None) -> None:
        pending, self._pending = self._pending, None
        self._close()
        if pending is not None and answer == "Yes":
            pending(client)

    def _close(self) -> None:
        if self._modal is not None:
            if self._question is not None:
                self._question.visible = False  # what the handle says once its dialog is gone
            self._modal.close()
            self._modal = None
