"""Who may move the arm: the access token of an exposed pendant and its checks on the HTTP API."""

from __future__ import annotations

from pendant.access.token import (
    SAFE_METHODS,
    TOKEN_HEADER,
    TOKEN_QUERY,
    changes_robot,
    is_loopback_host,
    is_stop,
    new_token,
    token_refusal,
    tokens_match,
    ui_url,
)

__all__ = [
    "SAFE_METHODS",
    "TOKEN_HEADER",
    "TOKEN_QUERY",
    "changes_robot",
    "is_loopback_host",
    "is_stop",
    "new_token",
    "token_refusal",
    "tokens_match",
    "ui_url",
]
