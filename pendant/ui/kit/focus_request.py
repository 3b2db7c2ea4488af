"""A question in one browser's panel that also puts the cursor where the answer goes.

The page's script (client_page.js, "focus on request") focuses the text box in the row labelled `label` when
an element carrying `data-pendant-focus` appears in the panel, and selects its text so typing replaces it.
`ask` numbers the questions: asking again is a new element, so it focuses again.
"""

from __future__ import annotations

import html

from pendant.ui.kit.html import inset


def focus_request(label: str, ask: int, question: str) -> str:
    """HTML for an html handle: `question` in bold, and the field labelled `label` focused on arrival."""
    return inset(
        f'<div data-pendant-focus="{html.escape(label)}" data-pendant-ask="{ask}">'
        f"<b>{html.escape(question, quote=False)}</b></div>"
    )
