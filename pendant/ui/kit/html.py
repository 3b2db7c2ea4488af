"""Small HTML helpers for the panels' own markup."""

from __future__ import annotations


def inset(content: str) -> str:
    """Top-level HTML lines up with viser's buttons, which sit inside the panel's side padding."""
    return f'<div style="padding:0 0.6rem;box-sizing:border-box;overflow-wrap:anywhere">{content}</div>'
