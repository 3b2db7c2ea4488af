"""The page's port (viser's websocket server) with the pendant's Host and Origin rules: a websocket from a
page of another origin never becomes a browser of the pendant (let alone its operator), a rebound host name
gets no page, and clients without an Origin (scripts, tests) connect as before. Real sockets on loopback."""

from __future__ import annotations

import os
import socket
import time
from collections.abc import Iterator

import httpx
import pytest
import viser
from websockets.exceptions import InvalidStatus
from websockets.sync.client import connect
from websockets.typing import Origin, Subprotocol

from pendant.access.origin import OriginPolicy
from pendant.sim import SimController
from pendant.ui.app import PendantUI
from tests.support.headless_viewer import CAMERA_HELLO
from tests.support.pages import new_page

SUBPROTOCOL = Subprotocol(f"viser-v{viser.__version__}")


@pytest.fixture
def page(sim: SimController) -> Iterator[PendantUI]:
    ui = new_page(sim, sim.arm, origins=OriginPolicy("127.0.0.1"))
    yield ui
    ui.stop()


def ws_url(page: PendantUI) -> str:
    return f"ws://127.0.0.1:{page.server.get_port()}/"


def test_a_websocket_from_another_origin_is_refused_and_nobody_gets_control(page: PendantUI) -> None:
    with pytest.raises(InvalidStatus) as refused:
        connect(
            ws_url(page), origin=Origin("http://evil.example"), subprotocols=[SUBPROTOCOL], open_timeout=30
        )
    assert refused.value.response.status_code == 403
    assert b"Cross-origin request refused" in refused.value.response.body
    assert page.desk.operator is None  # on main it became the operator and could jog


def test_a_rebound_host_name_gets_neither_the_page_nor_a_websocket(page: PendantUI) -> None:
    port = page.server.get_port()
    answer = httpx.get(f"http://127.0.0.1:{port}/", headers={"Host": f"evil.example:{port}"})
    assert answer.status_code == 403
    assert "--allowed-host" in answer.text
    upgrade = {
        "Host": "evil.example",
        "Connection": "Upgrade",
        "Upgrade": "websocket",
        "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ==",
        "Sec-WebSocket-Version": "13",
        "Sec-WebSocket-Protocol": SUBPROTOCOL,
    }
    assert httpx.get(f"http://127.0.0.1:{port}/", headers=upgrade).status_code == 403
    with pytest.raises(InvalidStatus) as refused:  # a second Host header besides the right one
        connect(ws_url(page), additional_headers={"Host": "evil.example"}, open_timeout=30)
    assert refused.value.response.status_code == 403
    assert page.desk.operator is None


def test_the_pendants_own_page_and_clients_without_an_origin_connect(page: PendantUI) -> None:
    port = page.server.get_port()
    served = httpx.get(f"http://localhost:{port}/")
    assert served.status_code == 200 and "text/html" in served.headers["content-type"]
    assert served.headers["content-security-policy"] == "frame-ancestors 'self'"
    for origin in (Origin(f"http://127.0.0.1:{port}"), Origin(f"http://localhost:{port}"), None):
        with connect(ws_url(page), origin=origin, subprotocols=[SUBPROTOCOL], open_timeout=30) as socket:
            assert socket.recv(timeout=30)  # viser's first messages: it is a connected browser


def test_a_closing_page_stops_a_held_jog_by_a_plain_get_and_a_foreign_host_cannot(
    page: PendantUI, sim: SimController
) -> None:
    from pendant.controller import MotionStatus
    from pendant.jog import JogFrame, JogRequest

    port = page.server.get_port()
    page.jogger.hold(JogRequest(JogFrame.JOINT, 0, +1, speed_percent=10))
    assert sim.get_motion_status() is MotionStatus.RUNNING
    refused = httpx.get(f"http://127.0.0.1:{port}/pendant-stop-jog", headers={"Host": f"evil.example:{port}"})
    assert refused.status_code == 403 and sim.get_motion_status() is MotionStatus.RUNNING
    answer = httpx.get(f"http://127.0.0.1:{port}/pendant-stop-jog")
    assert answer.status_code == 204
    assert page.jogger.active is None and sim.get_motion_status() is not MotionStatus.RUNNING
    # Nothing held: nothing to stop, and the answer is the same.
    assert httpx.get(f"http://127.0.0.1:{port}/pendant-stop-jog").status_code == 204


def masked_binary_frame(payload: bytes) -> bytes:
    """One websocket frame as a browser sends it (client frames are masked; RFC 6455 section 5.2)."""
    mask = os.urandom(4)
    length = len(payload)
    header = bytes([0x82]) + (
        bytes([0x80 | length]) if length < 126 else bytes([0x80 | 126]) + length.to_bytes(2, "big")
    )
    return header + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(payload))


LOST_WITHIN_S = 10.0  # ping interval + ping timeout + close timeout (5 s), and margin; the default was 50 s


@pytest.mark.measures  # the product's ~5 s to let a silent browser go, on the wall clock: not at nice 19
def test_a_browser_whose_connection_goes_silent_is_let_go_and_its_control_released(page: PendantUI) -> None:
    """A cable pulled: no close frame, no answer to pings. The operator's control (and a run it supervises)
    must not wait 20-40 s for the default keepalive."""
    port = page.server.get_port()
    silent = socket.create_connection(("127.0.0.1", port), timeout=30)
    try:
        silent.sendall(
            (
                "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
                f"Sec-WebSocket-Protocol: {SUBPROTOCOL}\r\n\r\n"
            ).encode()
        )
        assert silent.recv(4096).startswith(b"HTTP/1.1 101")
        silent.sendall(masked_binary_frame(CAMERA_HELLO))  # a viewer's first message, as viser's page sends
        connected = time.monotonic()
        while page.desk.operator is None:  # the first browser on this machine gets control
            assert time.monotonic() - connected < LOST_WITHIN_S, "the silent browser never joined"
            time.sleep(0.05)
        while page.desk.operator is not None:  # it reads nothing more and answers no ping
            assert time.monotonic() - connected < LOST_WITHIN_S, "a silent connection kept control"
            time.sleep(0.05)
    finally:
        silent.close()
