"""The page's "Join from a tablet" button: a QR code of the viewer URL, for people in the room to scan (they
watch; taking control still needs the token)."""

from __future__ import annotations

import html

import segno
import viser

from pendant.banner import interface_addresses, viewer_url
from pendant.ui.kit.gui_target import GuiTarget

QR_SCALE = 5  # SVG pixels per module: about 200 px across for a short URL


def join_urls(host: str, port: int) -> list[str]:
    return [viewer_url(address, port) for address in interface_addresses(host)]


def qr_html(urls: list[str]) -> str:
    """One QR code (inline SVG) and its URL per address."""
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
