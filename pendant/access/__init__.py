"""Who may move the arm: the access token of an exposed pendant and its checks on the HTTP API."""

from __future__ import annotations

from pendant.access.token import (
    MUTATING_METHODS,
    TOKEN_HEADER,
    TOKEN_QUERY,
    is_loopback_host,
    new_token,
    token_refusal,
    tokens_match,
    ui_url,
)

__all__ = [
    "MUTATING_METHODS",
    "TOKEN_HEADER",
    "TOKEN_QUERY",
    "is_loopback_host",
    "new_token",
    "token_refusal",
    "tokens_match",
    "ui_url",
]
