"""The start-up banner: where the page and the API are, as URLs other machines can open.

Bound to a wildcard (`--host 0.0.0.0` or `::`), the pendant is reachable at every address of the machine's
interfaces, so the banner prints one URL per real address (not `0.0.0.0`, which no browser can open, nor
loopback or link-local ones): a viewer URL, and with a token an operator URL carrying it, and a QR code of
the viewer URL in the terminal (segno), so a tablet in the room joins by scanning it.
"""

from __future__ import annotations

import io
import ipaddress
import sys
from dataclasses import dataclass
from typing import TextIO

import ifaddr
import segno

from pendant.access import TOKEN_HEADER, is_loopback_host, ui_url
from pendant.access.token import token_weakness
from pendant.config import Settings

WILDCARDS = ("0.0.0.0", "::", "")


def interface_addresses(host: str) -> list[str]:
    """The addresses other machines can reach the pendant at: `host` itself unless it is a wildcard; else
    each interface's IPv4 address (and global IPv6 ones when bound to `::`), loopback and link-local left
    out; loopback alone when the machine has nothing else."""
    if host not in WILDCARDS:
        return [host]
    found: list[str] = []
    for adapter in ifaddr.get_adapters():
        for ip in adapter.ips:
            text = ip.ip if isinstance(ip.ip, str) else ip.ip[0]  # IPv6 comes as (address, flow, scope)
            address = ipaddress.ip_address(text)
            if address.is_loopback or address.is_link_local or (address.version == 6 and host != "::"):
                continue
            if text not in found:
                found.append(text)
    return found or ["127.0.0.1"]


def viewer_url(address: str, port: int) -> str:
    return ui_url(address, port, None)


@dataclass(frozen=True)
class PageUrls:
    address: str
    viewer: str  # watch only
    operator: str | None  # carries the token: taking control needs nothing more


def page_urls(settings: Settings) -> list[PageUrls]:
    return [
        PageUrls(
            address,
            viewer_url(address, settings.ui_port),
            ui_url(address, settings.ui_port, settings.token) if settings.token is not None else None,
        )
        for address in interface_addresses(settings.host)
    ]


def qr_lines(url: str) -> str:
    """The URL as a QR code in the terminal (two modules per character cell: half blocks)."""
    out = io.StringIO()
    segno.make(url, error="m", micro=False).terminal(out=out, compact=True, border=2)
    return out.getvalue()


def announce(settings: Settings, out: TextIO | None = None, foxglove_port: int | None = None) -> None:
    """Print where things are served, first thing, so a user (or a test) knows where to go; `foxglove_port`:
    where the Foxglove live view listens (--foxglove-port, or the port the system gave for 0)."""
    out = out if out is not None else sys.stdout

    def say(line: str = "") -> None:
        print(line, file=out, flush=True)

    api = [f"http://{_bracketed(a)}:{settings.api_port}" for a in interface_addresses(settings.host)]
    source = settings.robot_url or f"simulated {settings.model}"
    if settings.time_scale != 1.0:
        source += f", {settings.time_scale:g}x time"
    say(f"PULSE REST API ({source}): {api[0]}  (docs: {api[0]}/docs, metrics: {api[0]}/metrics)")
    for other in api[1:]:
        say(f"    also {other}")
    if foxglove_port is not None:
        live = [f"ws://{_bracketed(a)}:{foxglove_port}" for a in interface_addresses(settings.host)]
        say(f"Foxglove live view: {live[0]}  (in Foxglove: Open connection > Foxglove WebSocket > that URL)")
        for other in live[1:]:
            say(f"    also {other}")
    if not settings.no_ui:
        urls = page_urls(settings)
        say(f"PULSE pendant: {urls[0].viewer}")
        if settings.token is not None:
            say("Open the pendant (and take control) with this URL:")
            say(f"    {urls[0].operator}")
        if len(urls) > 1 or not is_loopback_host(urls[0].address):
            for url in urls:
                say(f"  {url.address}: watch {url.viewer}")
                if url.operator is not None:
                    say(f"  {' ' * len(url.address)}  operate {url.operator}")
            say(f"Scan to watch on a tablet ({urls[0].viewer}):")
            out.write(qr_lines(urls[0].viewer))
            out.flush()
    if settings.token is not None:
        say(f"Access token: {settings.token}")
        say(f"API commands need the header  {TOKEN_HEADER}: {settings.token}  (PUT /freeze does not)")
        weakness = token_weakness(settings.token)
        if weakness is not None:
            print(
                f"WARNING: this access token is easy to guess: {weakness}. Omit --token for a strong one",
                file=sys.stderr,
                flush=True,
            )


def _bracketed(address: str) -> str:
    return f"[{address}]" if ":" in address and not address.startswith("[") else address
