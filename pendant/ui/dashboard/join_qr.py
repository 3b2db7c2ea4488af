"""The page's "Join from a tablet" button: a QR code of the viewer URL, for people in the room to scan (they
watch; taking control still needs the token).

Bound to loopback (the default) no tablet can reach the page: the dialog then says so and how to expose it
(`--host 0.0.0.0`), with the LAN addresses it would then answer at, rather than a QR code of 127.0.0.1."""

from __future__ import annotations

import html
import ipaddress

import segno
import viser

from pendant.banner import interface_addresses, viewer_url
from pendant.ui.kit.gui_target import GuiTarget

QR_SCALE = 5  # SVG pixels per module: about 200 px across for a short URL


def join_urls(host: str, port: int) -> list[str]:
    return [viewer_url(address, port) for address in interface_addresses(host)]


def loopback_only(urls: list[str]) -> bool:
    """Every URL names a loopback address (or localhost): nothing else on the network can open it."""
    hosts = [url.split("//", 1)[-1].rsplit(":", 1)[0].strip("[]") for url in urls]
    return all(host == "localhost" or _is_loopback(host) for host in hosts)


def _is_loopback(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def lan_note(port: int) -> str:
    """What to do when the page listens on loopback only: the command, and where a tablet would then go."""
    lan = [a for a in interface_addresses("0.0.0.0") if not _is_loopback(a)]
    where = ", ".join(html.escape(viewer_url(a, port)) for a in lan) or "this machine's LAN address"
    return (
        '<div id="join-loopback" style="margin:6px 0">This pendant listens on loopback only (127.0.0.1): '
        "a tablet cannot reach it. Restart it with <code>pendant --host 0.0.0.0</code> (it then prints an "
        f"access token for the operator); tablets on the LAN then join at {where}.</div>"
    )


def qr_html(urls: list[str]) -> str:
    """One QR code (inline SVG) and its URL per address; on loopback only, how to expose the page instead."""
    if urls and loopback_only(urls):
        port = int(urls[0].rstrip("/").rsplit(":", 1)[-1])
        return f'<div id="join-qr">{lan_note(port)}</div>'
    blocks = [
        f'<div style="text-align:center;margin:6px 0">{segno.make(url, error="m").svg_inline(scale=QR_SCALE)}'
        f'<div style="font-family:monospace;font-size:0.85em">{html.escape(url)}</div></div>'
        for url in urls
    ]
    return f'<div id="join-qr">{"".join(blocks)}</div>'


def add_join_button(target: GuiTarget, urls: list[str]) -> viser.GuiButtonHandle:
    """A button showing the QR codes in a dialog to whoever pressed it (viewers too: it changes nothing)."""
    button = target.gui.add_button("Join from a tablet (QR)", icon=viser.Icon.QRCODE)

    def show(event: viser.GuiEvent) -> None:
        where = event.client if event.client is not None else target
        with where.gui.add_modal("Scan to watch this pendant") as modal:
            where.gui.add_html(qr_html(urls))
            where.gui.add_button("Close").on_click(lambda _: modal.close())

    button.on_click(show)
    return button
