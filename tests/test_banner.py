"""The start-up banner on a LAN: one viewer and one operator URL per real interface address (never
0.0.0.0, loopback or link-local), and a QR code of the viewer URL; the page shows the same QR codes."""

from __future__ import annotations

import ipaddress
import re
import socket

import pytest

from pendant.access import ui_url
from pendant.banner import announce, interface_addresses, qr_lines
from pendant.cli import parse_settings, with_access_token
from pendant.sim import SimController
from pendant.ui.dashboard.join_qr import qr_html
from tests.support.doubles import fire
from tests.support.pages import new_page

UI_PORT, API_PORT = 9001, 9002


def primary_address() -> str:
    """The address this machine's default route leaves from (a UDP connect sends nothing)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        probe.connect(("192.0.2.1", 9))
        return str(probe.getsockname()[0])


def test_a_wildcard_bind_lists_real_addresses_only() -> None:
    addresses = interface_addresses("0.0.0.0")
    assert primary_address() in addresses
    for text in addresses:
        address = ipaddress.ip_address(text)
        assert not (address.is_unspecified or address.is_loopback or address.is_link_local)
        assert address.version == 4, "a 0.0.0.0 bind serves IPv4 only"
    assert interface_addresses("10.1.2.3") == ["10.1.2.3"], "bound to one address: that one"


def test_the_banner_prints_viewer_and_operator_urls_per_address_and_a_qr(
    capsys: pytest.CaptureFixture[str],
) -> None:
    settings = with_access_token(
        parse_settings(
            ["--host", "0.0.0.0", "--ui-port", str(UI_PORT), "--api-port", str(API_PORT), "--token", "T"]
        )
    )
    announce(settings)
    out = capsys.readouterr().out
    assert "0.0.0.0" not in out and "localhost" not in out
    for address in interface_addresses("0.0.0.0"):
        assert f"watch http://{address}:{UI_PORT}/" in out
        assert f"operate {ui_url(address, UI_PORT, 'T')}" in out
        assert f"http://{address}:{API_PORT}" in out
    viewer = f"http://{interface_addresses('0.0.0.0')[0]}:{UI_PORT}/"
    assert qr_lines(viewer) in out, "the QR code is the first viewer URL's"
    qr_rows = [line for line in out.splitlines() if re.fullmatch(r"[█▀▄ ]+", line)]
    assert len(qr_rows) >= 10, "a QR code of block characters"
    assert "T" not in "".join(qr_rows) and "token" not in viewer, "the QR code lets people watch, not operate"


def test_on_loopback_the_banner_stays_short(capsys: pytest.CaptureFixture[str]) -> None:
    announce(parse_settings(["--ui-port", str(UI_PORT)]))
    out = capsys.readouterr().out
    assert f"PULSE pendant: http://127.0.0.1:{UI_PORT}/" in out
    assert "█" not in out, "no QR code for a pendant only this machine can open"


def test_the_page_shows_the_viewer_qr_or_how_to_expose_the_page(sim: SimController) -> None:
    page = new_page(sim, sim.arm, mode_line="sim")
    try:
        session = page.open_session(page.server)
        assert session.join is not None
        assert page.join_urls == [f"http://127.0.0.1:{page.server.get_port()}/"]
        html = qr_html(page.join_urls)  # loopback: no QR code a tablet could not open, but how to expose it
        assert "<svg" not in html and "pendant --host 0.0.0.0" in html and "loopback only" in html
        lan = "http://192.168.1.20:8080/"
        assert qr_html([lan]).count("<svg") == 1 and lan in qr_html([lan])
        fire(session.join, None)  # pressed: the dialog opens with that QR code
    finally:
        page.stop()
