"""The access token: generated when the pendant is exposed beyond loopback, checked in constant time.

A browser hands the token over in the query of its websocket URL (`ws://HOST:PORT/?token=...`): viser's page
connects to the server named by its own `?websocket=` parameter, so the printed URL carries both (see
`ui_url`). API clients send it in the `X-Pendant-Token` header.

Tokens may hold any UTF-8 text (no spaces or control characters). HTTP header values are bytes: the header
matches when its bytes, or their percent-decoding (`caf%C3%A9`, for clients that can only send ASCII), equal
the token's UTF-8 bytes. A token in a URL (`?token=`) is percent-decoded as UTF-8, as URLs are.
"""

from __future__ import annotations

import hmac
import ipaddress
import secrets
import socket
from urllib.parse import quote, unquote_to_bytes

# Stopping is open to every client, as every browser may press Freeze: the operations table's stops need no
# token and are never refused for who sent them nor for their form (the Host and Origin rules still apply).
from pendant.controller.operations import is_stop

TOKEN_HEADER = "X-Pendant-Token"
TOKEN_QUERY = "token"
TOKEN_BYTES = 24  # 32 URL-safe characters
# GET, HEAD and OPTIONS only read; every other method (PUT, POST, PATCH, DELETE, PROPFIND, MOVE, ...) is
# treated as a command that can change the robot.
SAFE_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
# A token shorter than this, or of fewer distinct characters, is guessable: warned about at start-up.
STRONG_TOKEN_CHARS = 16
STRONG_TOKEN_DISTINCT = 8

MSG_TOKEN_MISSING = (
    f"This pendant is exposed on the network: send its access token in the {TOKEN_HEADER} header"
)
MSG_TOKEN_WRONG = f"Wrong access token in {TOKEN_HEADER}"
UNAUTHORIZED = 401
FORBIDDEN = 403


def new_token() -> str:
    return secrets.token_urlsafe(TOKEN_BYTES)


def changes_robot(method: str) -> bool:
    """Every method but GET, HEAD and OPTIONS counts as a command."""
    return method.upper() not in SAFE_METHODS


def tokens_match(given: str | None, expected: str) -> bool:
    """Constant-time comparison, so the time taken says nothing about how much of a guess was right."""
    if given is None:
        return False
    return hmac.compare_digest(given.strip().encode("utf-8"), expected.encode("utf-8"))


def header_matches(raw: bytes, expected: str) -> bool:
    """The header's bytes, or their percent-decoding, equal the token's UTF-8 bytes (both compared in
    constant time, whichever matches)."""
    want = expected.encode("utf-8")
    given = raw.strip()
    as_sent = hmac.compare_digest(given, want)
    decoded = hmac.compare_digest(unquote_to_bytes(given), want)
    return as_sent | decoded


def token_refusal(
    method: str, path: str, given: bytes | None, expected: str | None
) -> tuple[int, str] | None:
    """(status, message) when a request must be refused, None when it may go ahead.

    Reads and stops are always allowed; any other request needs the token when there is one: 401 without it,
    403 with a wrong one.
    """
    if expected is None or not changes_robot(method) or is_stop(method, path):
        return None
    if not given or not given.strip():
        return UNAUTHORIZED, MSG_TOKEN_MISSING
    if not header_matches(given, expected):
        return FORBIDDEN, MSG_TOKEN_WRONG
    return None


def token_problem(token: str) -> str | None:
    """Why `token` cannot be used (None when it can): it goes in a header, so no spaces or control
    characters."""
    if not token:
        return "the access token is empty"
    if any(ch.isspace() or not ch.isprintable() for ch in token):
        return "the access token must not contain spaces or control characters"
    return None


def token_weakness(token: str) -> str | None:
    """Why `token` is easy to guess, or None: short, or made of few distinct characters."""
    if len(token) < STRONG_TOKEN_CHARS:
        return f"it has {len(token)} characters (use at least {STRONG_TOKEN_CHARS})"
    if len(set(token)) < STRONG_TOKEN_DISTINCT:
        return f"it uses only {len(set(token))} different characters"
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
    """The URL to open the pendant's page; with a token, `?token=T` (the page hands it to its websocket)."""
    address = reachable_address(host)
    if ":" in address and not address.startswith("["):
        address = f"[{address}]"  # an IPv6 literal
    page = f"http://{address}:{port}/"
    if token is None:
        return page
    return f"{page}?{TOKEN_QUERY}={quote(token, safe='')}"
