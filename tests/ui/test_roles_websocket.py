"""The token in the page's URL reaches the server: viser's page opens its websocket at the URL given in its
`?websocket=` parameter, so `ws://HOST:PORT/?token=...` carries it. Real websocket clients on loopback."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable, Iterator
from urllib.parse import parse_qs, urlsplit

import pytest
import viser
import websockets

from pendant.access import ui_url
from pendant.controller import MotionStatus
from pendant.jog import JogFrame, JogRequest
from pendant.sim import MonotonicClock, SimController
from pendant.ui.app import PendantUI
from pendant.ui.page.roles import MSG_NO_TOKEN
from tests.support.headless_viewer import CAMERA_HELLO
from tests.support.pages import new_page
from tests.support.ports import free_port
from tests.support.waiting import SAFETY_NET_S

TOKEN = "url-token-123"
CONNECT_TIMEOUT_S = SAFETY_NET_S


@pytest.fixture
def exposed() -> Iterator[tuple[PendantUI, int]]:
    port = free_port()
    sim = SimController("pulse75", MonotonicClock())
    page = new_page(sim, sim.arm, port=port, token=TOKEN)
    page.start()
    yield page, port
    page.stop()


async def _wait_for(condition: Callable[[], bool], timeout_s: float = CONNECT_TIMEOUT_S) -> None:
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, "the pendant did not see the browser in time"
        await asyncio.sleep(0.05)


def test_printed_url_carries_the_token_as_jupyter_does() -> None:
    url = ui_url("192.168.1.20", 8080, TOKEN)
    assert url.startswith("http://192.168.1.20:8080/?token=")
    assert parse_qs(urlsplit(url).query)["token"] == [TOKEN]


def test_a_browser_whose_url_carries_the_token_can_take_control(exposed: tuple[PendantUI, int]) -> None:
    page, port = exposed
    protocol = [websockets.Subprotocol(f"viser-v{viser.__version__}")]

    async def scenario() -> None:
        async with (
            websockets.connect(
                f"ws://127.0.0.1:{port}/?token={TOKEN}",
                subprotocols=protocol,
                max_queue=None,
                open_timeout=SAFETY_NET_S,
            ) as with_token,
            websockets.connect(
                f"ws://127.0.0.1:{port}/", subprotocols=protocol, max_queue=None, open_timeout=SAFETY_NET_S
            ) as without,
        ):
            await with_token.send(CAMERA_HELLO)
            await without.send(CAMERA_HELLO)
            await _wait_for(lambda: len(page.sessions) == 2)
            sessions = sorted(page.sessions.values(), key=lambda s: s.client_id or 0)
            assert sessions[0].control.url_token == TOKEN and sessions[1].control.url_token is None
            assert "127.0.0.1" in page.desk.name(sessions[0].client_id)
            assert sessions[1].control.take() == MSG_NO_TOKEN
            assert sessions[0].control.take() is None
            operator = sessions[0].client_id
            assert page.desk.operator == operator

            # The operator jogs, then its browser goes away: the jog stops and control is released. No
            # deadman meanwhile: its 200 ms would end the jog by itself, and in a process starved of CPU
            # (the pass behind the timed tests, nice 19) before the test looks; the jog's own move lasts 3 s.
            page.jogger.stop_watchdog()
            assert page.jogger.hold(JogRequest(JogFrame.JOINT, 0, +1, 10.0))
            assert page.controller.get_motion_status() is MotionStatus.RUNNING
            await with_token.close()
            await _wait_for(lambda: page.desk.operator is None)
            await _wait_for(lambda: page.controller.get_motion_status() is MotionStatus.IDLE)
            assert page.jogger.active is None
            del without

    asyncio.run(scenario())
