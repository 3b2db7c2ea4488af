"""Cross-origin and DNS-rebinding defences: which `Host` a request may name, which `Origin` may change things.

The same rules as Jupyter's and Vite's dev servers, for both of the pendant's ports:

- `Host` must be an IP address (a DNS-rebinding attack needs a host *name* that the attacker's DNS points at
  this machine), a loopback name (`localhost`, `*.localhost`), the name the pendant is bound to, or a name
  given with `--allowed-host` (`.example.com` allows its subdomains too). Anything else: 403.
- A request carrying an `Origin` (every browser sends one with a POST, PUT or websocket, even in `no-cors`
  mode) must come from the pendant's own origin (scheme, host and port of the `Host` it asked for; the
  loopback names count as one). A page from elsewhere gets 403 before anything reaches the arm.
- A command from a page with its body in a type a page may send without CORS (`text/plain`, form types) is
  refused with 415: a page sends JSON as `application/json`. A stop is never refused for its form.

A request with neither `Origin` nor any `Sec-Fetch-*` header was not sent by a page (every browser in use
adds one or the other to a command): curl, urllib, httpx, Rozum's SDK, the exported scripts. The Origin and
content-type rules do not apply to it (`curl -d` and urllib send form encoding by default; the body is read as
JSON whatever its type), only the Host rule.
"""

from __future__ import annotations

import ipaddress
from collections.abc import Iterable
from dataclasses import dataclass
from urllib.parse import urlsplit

from pendant.access.token import is_loopback_host

FORBIDDEN = 403
UNSUPPORTED_MEDIA_TYPE = 415
# The content types a page may send cross-origin without asking first (the CORS "simple" ones).
SIMPLE_CONTENT_TYPES = frozenset({"text/plain", "application/x-www-form-urlencoded", "multipart/form-data"})
MAX_SHOWN_CHARS = 80  # an echoed header is cut to this: refusals stay small whatever was sent
WILDCARD_BINDS = frozenset({"", "0.0.0.0", "::", "[::]"})


def _shown(text: str) -> str:
    return text if len(text) <= MAX_SHOWN_CHARS else text[:MAX_SHOWN_CHARS] + "…"


def split_host(host_header: str) -> tuple[str, int | None]:
    """`'[::1]:8080'` -> `('::1', 8080)`, `'Example.COM.'` -> `('example.com', None)`; else ValueError."""
    text = host_header.strip()
    if text.startswith("["):
        name, _, rest = text[1:].partition("]")
        port_text = rest[1:] if rest.startswith(":") else ""
        if rest and not rest.startswith(":"):
            raise ValueError(host_header)
    elif text.count(":") == 1:
        name, _, port_text = text.partition(":")
    else:
        name, port_text = text, ""
    port = int(port_text) if port_text else None
    if not name or (port is not None and not 0 < port < 65536):
        raise ValueError(host_header)
    return name.lower().rstrip("."), port


def _is_ip(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True


def _is_loopback_name(name: str) -> bool:
    return is_loopback_host(name) or name.endswith(".localhost")


@dataclass(frozen=True)
class OriginPolicy:
    """The Host and Origin rules of one pendant: `bound_host` is its `--host`, `allowed_hosts` its
    `--allowed-host` names."""

    bound_host: str = "127.0.0.1"
    allowed_hosts: tuple[str, ...] = ()

    @classmethod
    def for_binding(cls, bound_host: str, allowed_hosts: Iterable[str] = ()) -> OriginPolicy:
        return cls(bound_host, tuple(h.strip().lower().rstrip(".") for h in allowed_hosts if h.strip()))

    def host_allowed(self, host_header: str | None) -> bool:
        if host_header is None:  # HTTP/1.0 without Host: no browser sends that
            return True
        try:
            name, _port = split_host(host_header)
        except ValueError:
            return False
        if _is_ip(name) or _is_loopback_name(name):
            return True
        if self.bound_host.lower() not in WILDCARD_BINDS and name == self.bound_host.lower().rstrip("."):
            return True
        return any(
            name == allowed or (allowed.startswith(".") and name.endswith(allowed))
            for allowed in self.allowed_hosts
        )

    def same_origin(self, origin: str, host_header: str | None) -> bool:
        """True when `origin` is the pendant's own: the scheme's host and port are those `Host` named."""
        if host_header is None:
            return False
        try:
            parts = urlsplit(origin)
            origin_port = parts.port or {"http": 80, "https": 443}.get(parts.scheme)
            host, port = split_host(host_header)
        except ValueError:
            return False
        if parts.scheme not in ("http", "https") or not parts.hostname or origin_port is None:
            return False
        if origin_port != (port or {"http": 80, "https": 443}[parts.scheme]):
            return False
        origin_host = parts.hostname.lower().rstrip(".")
        return origin_host == host or (_is_loopback_name(origin_host) and _is_loopback_name(host))

    def host_refusal(self, host_header: str | None) -> tuple[int, str] | None:
        if self.host_allowed(host_header):
            return None
        shown = _shown(host_header or "")
        return FORBIDDEN, (
            f"Host {shown} is not allowed: open the pendant by its IP address or localhost, "
            "or start it with --allowed-host NAME"
        )

    def origin_refusal(self, origin: str | None, host_header: str | None) -> tuple[int, str] | None:
        if origin is None or self.same_origin(origin, host_header):
            return None
        return (
            FORBIDDEN,
            f"Cross-origin request refused: a page from {_shown(origin)} may not command the pendant",
        )

    def request_refusal(
        self,
        host_header: str | None,
        origin: str | None,
        content_type: str | None,
        *,
        changes: bool,
        from_page: bool = True,
        stop: bool = False,
    ) -> tuple[int, str] | None:
        """(status, message) for an HTTP request that must be refused, None when it may go on.

        Every request has its Host checked; one that `changes` something also its Origin and, when it comes
        `from_page` and is no `stop`, its content type.
        """
        refusal = self.host_refusal(host_header)
        if refusal is not None or not changes:
            return refusal
        refusal = self.origin_refusal(origin, host_header)
        if refusal is not None or stop or not from_page:
            return refusal
        media_type = (content_type or "").split(";", 1)[0].strip().lower()
        if media_type in SIMPLE_CONTENT_TYPES:
            return UNSUPPORTED_MEDIA_TYPE, (
                f"Unsupported content type {_shown(media_type)}: send JSON bodies as application/json"
            )
        return None

    def handshake_refusal(self, host_header: str | None, origin: str | None) -> tuple[int, str] | None:
        """For the page's port: a page load or websocket upgrade must name an allowed Host and, when it has an
        Origin, come from the pendant's own page."""
        return self.host_refusal(host_header) or self.origin_refusal(origin, host_header)
