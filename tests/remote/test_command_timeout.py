"""Finding 3 of the audit: commands through the proxy are never left in doubt. A slow controller's answer to a
command arrives (no 502 for a command it then runs in full); a lost answer is 504 saying the command may have
run, sent once; reads keep the short timeout."""

from __future__ import annotations

import threading
import time

import httpx

from pendant.remote import create_proxy_app
from pendant.remote.proxy import MSG_MAY_HAVE_RUN
from tests.support.bad_servers import http_answer, raw_server, request_path
from tests.support.ports import free_port
from tests.support.threads import serve_in_thread
from tests.support.waiting import SAFETY_NET_S

READ_TIMEOUT_S = 0.3
COMMAND_TIMEOUT_S = 3.0
SLOW_ANSWER_S = 1.0  # longer than the read timeout, shorter than the command timeout
CLIENT_TIMEOUT_S = SAFETY_NET_S


class SlowController:
    """Answers every request after `delay_s` (None: never), counting what it received."""

    def __init__(self, delay_s: float | None) -> None:
        self.delay_s = delay_s
        self.received: list[str] = []
        self._lock = threading.Lock()

    def __call__(self, head: bytes) -> bytes | None:
        with self._lock:
            self.received.append(head.split(b" ", 1)[0].decode() + " " + request_path(head))
        if self.delay_s is None:
            return None
        time.sleep(self.delay_s)
        return http_answer("200 OK", b"")


def test_a_slow_answer_to_a_command_comes_through_instead_of_a_502() -> None:
    controller = SlowController(SLOW_ANSWER_S)
    with (
        raw_server(controller) as robot_url,
        serve_in_thread(
            create_proxy_app(robot_url, read_timeout=READ_TIMEOUT_S, command_timeout=COMMAND_TIMEOUT_S)
        ) as proxy_url,
        httpx.Client(base_url=proxy_url, timeout=CLIENT_TIMEOUT_S) as client,
    ):
        answer = client.put("/pose?speed=10", json={"angles": [0.0] * 6})
        assert answer.status_code == 200  # the controller ran it and said so: the client knows
        slow_read = client.get("/pose")
        assert slow_read.status_code == 502  # reads keep the short timeout (and are retried, being GETs)
        assert f"no answer within {READ_TIMEOUT_S:g} s" in slow_read.text
    assert controller.received.count("PUT /pose?speed=10") == 1


def test_a_lost_answer_to_a_command_is_504_saying_it_may_have_run_and_it_is_sent_once() -> None:
    controller = SlowController(None)
    with (
        raw_server(controller) as robot_url,
        serve_in_thread(
            create_proxy_app(robot_url, read_timeout=READ_TIMEOUT_S, command_timeout=0.5)
        ) as proxy_url,
        httpx.Client(base_url=proxy_url, timeout=CLIENT_TIMEOUT_S) as client,
    ):
        answer = client.post("/poses/run?speed=10", json=[{"angles": [0.0] * 6}])
        assert answer.status_code == 504
        assert MSG_MAY_HAVE_RUN in answer.text
        assert "POST /poses/run" in answer.text
    assert controller.received == ["POST /poses/run?speed=10"]


def test_a_command_that_could_not_be_delivered_is_502_and_says_so() -> None:
    app = create_proxy_app(f"http://127.0.0.1:{free_port()}", connect_timeout=0.5)
    with serve_in_thread(app) as proxy_url, httpx.Client(base_url=proxy_url) as client:
        answer = client.put("/signal/output/1/high")
        assert answer.status_code == 502
        assert "not sent" in answer.text
