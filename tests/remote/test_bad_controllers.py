"""The client and the proxy against controllers that misbehave on the wire (real sockets on 127.0.0.1):
one that never answers, one that speaks no HTTP, one that answers HTTP 200 with garbage, one that is gone."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import httpx
import pytest

from pendant.controller.errors import ControllerOffline
from pendant.controller.types import MotionStatus
from pendant.remote import RemoteController, create_proxy_app
from tests.support.bad_servers import http_answer, raw_server, request_path
from tests.support.ports import free_port
from tests.support.threads import serve_in_thread

# Short timeouts keep each test to a fraction of a second; the defaults (1 s / 3 s) behave the same.
CONNECT_TIMEOUT_S = 0.5
READ_TIMEOUT_S = 0.3
PASSING_READ_TIMEOUT_S = 3.0  # the hung call waits this out (each of its tries): the test takes 3 s or more
HUNG_CALL_BOUND_S = 120.0  # however many tries the hung call makes, on a starved machine
IDLE_ANSWER = http_answer("200 OK", b'"IDLE"')


def hang_on_pose(head: bytes) -> bytes | None:
    """Answers GET /status/motion; accepts GET /pose and never answers it."""
    return None if request_path(head) == "/pose" else IDLE_ANSWER


def remote(url: str, read_timeout: float = READ_TIMEOUT_S) -> RemoteController:
    return RemoteController(url, connect_timeout=CONNECT_TIMEOUT_S, read_timeout=read_timeout)


def test_a_hung_controller_times_out_and_other_calls_still_work() -> None:
    # The call after the hung one must be answered by this process's server thread within the read time-out:
    # 0.3 s was too short behind the timed pass (nice 19, starved for seconds), so the longer one here.
    with raw_server(hang_on_pose) as url, remote(url, PASSING_READ_TIMEOUT_S) as controller:
        with pytest.raises(ControllerOffline, match=r"did not answer GET /pose within 3 s"):
            controller.get_pose()
        assert not controller.health().online
        # The hung connection was dropped; the client is not wedged.
        assert controller.get_motion_status() is MotionStatus.IDLE
        assert controller.health().online


def test_calls_from_another_thread_pass_a_hung_one() -> None:
    # The call that passes must be answered within the read time-out by a server thread of this process,
    # which a starved machine (the pass behind the timed one, nice 19) may not run for 0.3 s (CI, 27 Nov).
    with raw_server(hang_on_pose) as url, remote(url, read_timeout=PASSING_READ_TIMEOUT_S) as controller:
        outcome: list[Exception] = []

        def read_pose() -> None:
            try:
                controller.get_pose()
            except Exception as exc:
                outcome.append(exc)

        hung = threading.Thread(target=read_pose)
        hung.start()
        assert controller.get_motion_status() is MotionStatus.IDLE
        hung.join(timeout=HUNG_CALL_BOUND_S)
        assert len(outcome) == 1 and isinstance(outcome[0], ControllerOffline)


def test_a_controller_speaking_no_http_is_offline() -> None:
    with raw_server(lambda _head: b"SSH-2.0-OpenSSH_9.6\r\n\r\n") as url, remote(url) as controller:
        with pytest.raises(ControllerOffline, match="no valid HTTP answer to GET /pose"):
            controller.get_pose()
        with pytest.raises(ControllerOffline):
            controller.relax()
        assert not controller.health().online


def test_a_controller_answering_html_to_get_pose_is_offline() -> None:
    page = http_answer("200 OK", b"<html><body>Router login</body></html>", "text/html")
    with (
        raw_server(lambda _head: page) as url,
        remote(url) as controller,
        pytest.raises(ControllerOffline, match=r"Unparsable answer .* GET /pose: '<html>"),
    ):
        controller.get_pose()


def test_a_port_where_nothing_listens_is_offline() -> None:
    with remote(f"http://127.0.0.1:{free_port()}") as controller:
        with pytest.raises(ControllerOffline, match="unreachable"):
            controller.get_motion_status()
        health = controller.ping()
        assert not health.online and health.last_seen is None


@pytest.fixture
def proxy_to_hung_controller() -> Iterator[str]:
    with raw_server(hang_on_pose) as robot_url:
        app = create_proxy_app(robot_url, connect_timeout=CONNECT_TIMEOUT_S, read_timeout=READ_TIMEOUT_S)
        with serve_in_thread(app) as proxy_url:
            yield proxy_url


def test_the_proxy_answers_502_when_the_controller_hangs(proxy_to_hung_controller: str) -> None:
    with httpx.Client(base_url=proxy_to_hung_controller) as client:
        answer = client.get("/pose")
        assert answer.status_code == 502
        assert answer.headers["content-type"].startswith("text/plain")
        assert "did not answer GET /pose" in answer.text
        # Other requests go through meanwhile.
        assert client.get("/status/motion").content == b'"IDLE"'


def test_the_proxy_answers_502_when_the_controller_speaks_no_http() -> None:
    with (
        raw_server(lambda _head: b"\x00\x01garbage\r\n\r\n") as robot_url,
        serve_in_thread(create_proxy_app(robot_url, connect_timeout=CONNECT_TIMEOUT_S)) as proxy_url,
        httpx.Client(base_url=proxy_url) as client,
    ):
        answer = client.get("/pose")
        assert answer.status_code == 502
        assert "no valid HTTP answer" in answer.text


def test_the_proxy_answers_502_when_the_controller_is_gone() -> None:
    app = create_proxy_app(f"http://127.0.0.1:{free_port()}", connect_timeout=CONNECT_TIMEOUT_S)
    with serve_in_thread(app) as proxy_url, httpx.Client(base_url=proxy_url) as client:
        answer = client.put("/pose?speed=10", json={"angles": [0] * 6})
        assert answer.status_code == 502
        assert "unreachable" in answer.text
        health = client.get("/pendant/health").json()
        assert health["mode"] == "robot" and health["online"] is False
        assert "unreachable" in health["last_error"]
