"""The access token: generated when the pendant is exposed beyond loopback, checked in constant time.

A browser hands the token over in the query of its websocket URL (`ws://HOST:PORT/?token=...`): viser's page
connects to the server named by its own `?websocket=` parameter, so the printed URL carries both (see
`ui_url`). API clients send it in the `X-Pendant-Token` header.
"""

from __future__ import annotations

import hmac
import ipaddress
import secrets
import socket
from urllib.parse import quote

TOKEN_HEADER = "X-Pendant-Token"
TOKEN_QUERY = "token"
TOKEN_BYTES = 24  # 32 URL-safe characters
# Every request that can change the robot; GET, HEAD and OPTIONS only read.
MUTATING_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})

MSG_TOKEN_MISSING = (
    f"This pendant is exposed on the network: send its access token in the {TOKEN_HEADER} header"
)
MSG_TOKEN_WRONG = f"Wrong access token in {TOKEN_HEADER}"
UNAUTHORIZED = 401
FORBIDDEN = 403


def new_token() -> str:
    return secrets.token_urlsafe(TOKEN_BYTES)


def tokens_match(given: str | None, expected: str) -> bool:
    """Constant-time comparison, so the time taken says nothing about how much of a guess was right."""
    if given is None:
        return False
    return hmac.compare_digest(given.strip().encode(), expected.encode())


def token_refusal(method: str, given: str | None, expected: str | None) -> tuple[int, str] | None:
    """(status, message) when a request must be refused, None when it may go ahead.

    Reads are always allowed; a mutating request needs the token when there is one: 401 without it, 403 with
    a wrong one.
    """
    if expected is None or method.upper() not in MUTATING_METHODS:
        return None
    if not given:
        return UNAUTHORIZED, MSG_TOKEN_MISSING
    if not tokens_match(given, expected):
        return FORBIDDEN, MSG_TOKEN_WRONG
    return None


def is_loopback_host(host: str) -> bool:
    """True for the addresses only this machine can reach (127.0.0.0/8, ::1, localhost)."""
    if host.strip().lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False  # a host name: it may resolve to anything, treat it as exposed


def reachable_address(host: str) -> str:
    """An address other machines can use for `host`: the primary LAN address for a wildcard bind."""
    if host not in ("0.0.0.0", "::", ""):
        return host
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.1", 9))  # TEST-NET-1: no packet is sent by a UDP connect
            return probe.getsockname()[0]
        except OSError:
            return socket.gethostname()


def ui_url(host: str, port: int, token: str | None) -> str:
    """The URL to open the pendant's page; with a token it rides in the page's websocket URL."""
    address = reachable_address(host)
    if ":" in address and not address.startswith("["):
        address = f"[{address}]"  # an IPv6 literal
    page = f"http://{address}:{port}/"
    if token is None:
        return page
    websocket = f"ws://{address}:{port}/?{TOKEN_QUERY}={token}"
    return f"{page}?websocket={quote(websocket, safe='')}"
